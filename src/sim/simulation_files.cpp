#include "robcal/sim/simulation_files.hpp"

#include <fmt/format.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <utility>
#include <vector>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "yaml_list.hpp"

namespace robcal {

std::string instrument_to_yaml(const VirtualInstrument& instrument) {
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << YAML::BeginMap << YAML::Key << "instrument" << YAML::Value
      << instrument_name(instrument.kind);
  switch (instrument.kind) {
    case InstrumentKind::LaserTracker: {
      const LaserTracker& t = instrument.tracker;
      out << YAML::Key << "position_mm" << YAML::Value << YAML::Flow << as_list(t.position_mm)
          << YAML::Key << "sigma_mm" << YAML::Value << YAML::Flow << as_list(t.sigma_mm)
          << YAML::Key << "cone_half_angle_deg" << YAML::Value << t.cone_half_angle_deg;
      break;
    }
    case InstrumentKind::OpticalCmm: {
      const OpticalCmm& c = instrument.cmm;
      out << YAML::Key << "position_mm" << YAML::Value << YAML::Flow << as_list(c.position_mm)
          << YAML::Key << "sigma_mm" << YAML::Value << c.sigma_mm << YAML::Key
          << "sigma_orientation_deg" << YAML::Value << c.sigma_orientation_deg << YAML::Key
          << "facing_limit_deg" << YAML::Value << c.facing_limit_deg;
      break;
    }
    case InstrumentKind::Ballbar: {
      const Ballbar& b = instrument.ballbar;
      out << YAML::Key << "centre_mm" << YAML::Value << YAML::Flow << as_list(b.centre_mm)
          << YAML::Key << "nominal_length_mm" << YAML::Value << b.nominal_length_mm << YAML::Key
          << "sigma_mm" << YAML::Value << b.sigma_mm << YAML::Key << "range_mm" << YAML::Value
          << b.range_mm;
      break;
    }
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

SimulationFiles write_simulation(const std::filesystem::path& dir, const std::string& stem,
                                 const SimulationResult& result, const Tool& tool,
                                 const VirtualInstrument& instrument, const TrueRobot& truth,
                                 const std::string& robot_name, const std::string& comment) {
  // A 6D instrument measures the TCP frame: the tool file says which, even when it is the flange.
  Tool written = tool;
  written.tcp_given = tool.tcp_given || result.measurements.kind == MeasurementKind::Poses;
  namespace fs = std::filesystem;
  const std::vector<std::pair<fs::path, std::string>> contents{
      {stem + ".csv", write_measurements_csv(result.measurements, tool, comment)},
      {"tool.yaml", tool_to_yaml(written)},
      {"instrument.yaml", instrument_to_yaml(instrument)},
      {fs::path("truth") / "truth.yaml", truth_to_yaml(truth, robot_name)}};
  // The folder appears whole or not at all: every file is written into a staging folder beside
  // it first, so a full disk or a crash leaves the target as it was.
  fs::path target = fs::absolute(dir).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();
  refuse_non_folder(dir);
  std::error_code ec;
  const fs::path staging =
      target.parent_path() /
      fmt::format(".{}.partial-{}", target.filename().string(), static_cast<long>(::getpid()));
  try {
    fs::remove_all(staging);
    for (const auto& [name, text] : contents) write_file_atomically(staging / name, text);
    if (!fs::exists(target) || fs::is_empty(target)) {
      fs::remove(target, ec);  // an empty folder given as --out
      fs::rename(staging, target);
    } else {
      // The folder holds other files (an earlier run): replace ours one by one, each by rename.
      fs::create_directories(target / "truth");
      for (const auto& [name, text] : contents) fs::rename(staging / name, target / name);
      fs::remove_all(staging);
    }
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(staging, ec);
    throw InputError({dir.string(), 0, 0, "--out"},
                     fmt::format("cannot write the simulation folder: {}", e.code().message()));
  } catch (...) {
    fs::remove_all(staging, ec);
    throw;
  }
  return {dir / contents[0].first, dir / contents[1].first, dir / contents[2].first,
          dir / contents[3].first};
}

}  // namespace robcal
