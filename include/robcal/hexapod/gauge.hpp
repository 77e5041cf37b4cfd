#pragma once
/// \file
/// The length gauge the hexapod measures with (docs/method/06-instruments.md §1, 07-hexapod.md §5):
/// it reads only within ±range of its set-up length, with standard uncertainty σ. The published
/// ballbar reads ±1 mm with σ = 0.51 µm; a longer-range gauge (issue 20: ±5 mm) reaches the poses
/// of an uncalibrated robot, at the price of its own σ. Where the range and σ go:
/// HexapodCellOptions (simulation), SessionPlan (session), and σ times the σ-multiples of
/// uncertainty.hpp / four_cup_kinematics.hpp.

#include <string>

#include "robcal/hexapod/poses.hpp"

namespace robcal::hexapod {

struct LengthGauge {
  double range_mm = 1.0;      ///< readable within set-up length ± range
  double sigma_mm = 0.00051;  ///< standard uncertainty of one reading
};

/// Throws InputError naming `range_key` or `sigma_key` (e.g. the CLI flags) when the range or σ
/// is not a positive finite length, or when σ is not below the range (a gauge whose noise covers
/// its range reads nothing).
void check_gauge(const LengthGauge& gauge, const std::string& range_key,
                 const std::string& sigma_key);

/// Empty when the gauge can measure every fixture side: the base sides at the legs' set-up
/// (geometry.leg_mm, docs/method/08-world-frame.md §3 step 4) and the tool sides at `tool_setup_mm`
/// (step 1). Otherwise the first side out of reach, with the reach and what to do.
std::string fixture_range_problem(const HexapodGeometry& geometry, double tool_setup_mm,
                                  const LengthGauge& gauge);

/// The same for a plan (tool sides at their own nominal length), as an InputError with key
/// "--gauge-range-mm": such fixtures are out of range at every placement.
void check_fixture_range(const HexapodGeometry& geometry, const LengthGauge& gauge);

}  // namespace robcal::hexapod
