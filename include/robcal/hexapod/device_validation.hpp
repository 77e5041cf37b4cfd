#pragma once
/// \file
/// Validation of the ballbar hexapod itself (issue 20 item 4, docs/method/07-hexapod.md §7): the
/// published experimental validation — the device's tool-fixture poses against an independent
/// instrument measuring the tool cups — simulated. For each assembly mode, random poses whose legs
/// the gauge can read (every leg within 0.8 × the range of its set-up length) are measured twice:
/// by the device (12 distances with the gauge σ, direct kinematics) and by the reference instrument
/// (each tool cup with σ per axis). The device's pose uncertainty per mode is reported as the GUM
/// predicts it (exact sensitivities of the cascade at each pose) and as the comparisons show it:
/// device − truth, and device − reference, which must agree with √(u_device² + u_reference²).

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/gauge.hpp"
#include "robcal/hexapod/poses.hpp"

namespace robcal::hexapod {

struct DeviceValidationRequest {
  HexapodGeometry geometry;  ///< the fixtures (true = nominal here) and the legs' set-up length
  LengthGauge gauge;
  double reference_sigma_mm = 0.005;  ///< per axis of each tool cup (e.g. an optical CMM)
  int poses_per_mode = 500;
  uint64_t seed = 1;
};

struct ModeValidation {
  int mode = 0;
  int poses = 0;  ///< drawn poses with a real solution in this mode
  /// Tool-fixture centroid, mm: GUM standard uncertainty (RMS over the poses of √tr(J·Jᵀ)·σ), the
  /// observed RMS distance device − truth, the reference's own (σ_ref/√3 per axis for the mean of
  /// three cups: σ_ref as a norm), the observed RMS device − reference and its prediction
  /// √(u_device² + u_reference²).
  double centroid_gum_mm = 0, centroid_vs_truth_mm = 0;
  double centroid_reference_mm = 0, centroid_vs_reference_mm = 0, centroid_predicted_mm = 0;
  /// Orientation of the tool fixture frame (rotation angle, deg, RMS): device − truth, device −
  /// reference.
  double orientation_vs_truth_deg = 0, orientation_vs_reference_deg = 0;
  /// Worst tool-cup GUM uncertainty (norm) over the poses, in multiples of the gauge σ
  /// (published ≈ 3.2 at the nominal poses).
  double worst_cup_sigma_multiple = 0;
};

struct DeviceValidation {
  std::vector<ModeValidation> modes;
};

/// Throws InputError on bad fixtures, gauge, reference σ or pose count (1..1,000,000).
DeviceValidation validate_device(const DeviceValidationRequest& request);

nlohmann::json device_validation_json(const DeviceValidation& v,
                                      const DeviceValidationRequest& request);

}  // namespace robcal::hexapod
