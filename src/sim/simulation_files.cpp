#include "robcal/sim/simulation_files.hpp"

#include <yaml-cpp/yaml.h>

#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace robcal {
namespace {

std::vector<double> as_list(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

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
  SimulationFiles files{dir / (stem + ".csv"), dir / "tool.yaml", dir / "instrument.yaml",
                        dir / "truth" / "truth.yaml"};
  // Everything is rendered before the first file is written, so a failure leaves no file.
  const std::string measurements = write_measurements_csv(result.measurements, tool, comment);
  // A 6D instrument measures the TCP frame: the tool file says which, even when it is the flange.
  Tool written = tool;
  written.tcp_given = tool.tcp_given || result.measurements.kind == MeasurementKind::Poses;
  const std::string tool_text = tool_to_yaml(written);
  const std::string instrument_text = instrument_to_yaml(instrument);
  const std::string truth_text = truth_to_yaml(truth, robot_name);
  write_file_atomically(files.measurements, measurements);
  write_file_atomically(files.tool, tool_text);
  write_file_atomically(files.instrument, instrument_text);
  write_file_atomically(files.truth, truth_text);
  return files;
}

}  // namespace robcal
