#pragma once
/// \file
/// The simulated hexapod calibration's report (end_to_end.hpp) as JSON, beside the published
/// figures of the real LR Mate 200iC: what `robcal hexapod simulate --json` prints.

#include <cstdint>

#include <nlohmann/json_fwd.hpp>

#include "robcal/hexapod/end_to_end.hpp"

namespace robcal::hexapod {

/// Stages and validation figures to 1e-6 mm; `seed` is the one the run drew from.
nlohmann::json end_to_end_json(const EndToEndReport& report, const EndToEndOptions& options,
                               uint64_t seed);

}  // namespace robcal::hexapod
