#include "robcal/hexapod/gauge.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <tuple>

#include "robcal/core/error.hpp"

namespace robcal::hexapod {

void check_gauge(const LengthGauge& gauge, const std::string& range_key,
                 const std::string& sigma_key) {
  if (!std::isfinite(gauge.range_mm) || gauge.range_mm <= 0)
    throw InputError({"", 0, 0, range_key},
                     fmt::format("gauge range {} mm is not a positive length (the ballbar "
                                 "reads ±1 mm, a long-range gauge e.g. ±5 mm)",
                                 gauge.range_mm));
  if (!std::isfinite(gauge.sigma_mm) || gauge.sigma_mm <= 0)
    throw InputError({"", 0, 0, sigma_key},
                     fmt::format("gauge σ {} mm is not a positive length (the ballbar: "
                                 "0.00051 mm)",
                                 gauge.sigma_mm));
  if (gauge.sigma_mm >= gauge.range_mm)
    throw InputError({"", 0, 0, sigma_key},
                     fmt::format("gauge σ {} mm is not below its range ±{} mm: check the "
                                 "units (mm)",
                                 gauge.sigma_mm, gauge.range_mm));
}

std::string fixture_range_problem(const HexapodGeometry& g, double tool_setup_mm,
                                  const LengthGauge& gauge) {
  static constexpr std::array<const char*, 3> kNames{"12", "23", "31"};
  for (const auto& [sides, letter, setup] : {std::tuple{g.base.as_array(), 'b', g.leg_mm},
                                             std::tuple{g.tool.as_array(), 't', tool_setup_mm}})
    for (int i = 0; i < 3; ++i)
      if (!(std::abs(sides[i] - setup) <= gauge.range_mm))
        return fmt::format(
            "fixture side {}{} = {} mm is out of the gauge's reach {} ± {} mm: make the fixture "
            "sides within the range of the set-up length or use a longer-range gauge",
            letter, kNames[i], sides[i], setup, gauge.range_mm);
  return {};
}

void check_fixture_range(const HexapodGeometry& geometry, const LengthGauge& gauge) {
  if (const std::string problem = fixture_range_problem(geometry, geometry.tool.d12, gauge);
      !problem.empty())
    throw InputError({"", 0, 0, "--gauge-range-mm"}, problem);
}

}  // namespace robcal::hexapod
