#include "robcal/sim/simulator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal {

namespace {

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream stream(line);
  std::string cell;
  while (std::getline(stream, cell, ',')) {
    const auto first = cell.find_first_not_of(" \t\r");
    const auto last = cell.find_last_not_of(" \t\r");
    cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
  }
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

/// Column of each cell's start (1-based), for error messages.
int cell_column(const std::string& line, size_t cell) {
  size_t pos = 0;
  for (size_t k = 0; k < cell; ++k) pos = line.find(',', pos) + 1;
  return static_cast<int>(pos) + 1;
}

}  // namespace

std::vector<ConfigurationRow> parse_configuration_rows(const std::string& text,
                                                       const std::string& path) {
  std::stringstream stream(text);
  std::string line;
  int line_number = 0;
  std::vector<std::string> header;
  int config_col = -1, target_col = -1, approach_col = -1, payload_col = -1;
  std::array<int, kJointCount> joint_cols{};
  std::vector<ConfigurationRow> configs;
  std::map<std::string, int> first_line;  // configuration label → its line
  double largest_deg = 0;
  constexpr double kMaxJointDeg = 1080;
  while (std::getline(stream, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = split_csv_line(line);
    if (header.empty()) {
      header = cells;
      auto find = [&](const std::string& name) {
        const auto it = std::find(header.begin(), header.end(), name);
        return it == header.end() ? -1 : static_cast<int>(it - header.begin());
      };
      config_col = find("config");
      target_col = find("target");
      approach_col = find("approach");
      payload_col = find("payload");
      for (int j = 0; j < kJointCount; ++j) {
        joint_cols[static_cast<size_t>(j)] = find(fmt::format("j{}", j + 1));
        if (joint_cols[static_cast<size_t>(j)] < 0)
          throw InputError({path, line_number, 0, fmt::format("j{}", j + 1)},
                           "missing column; a configurations file has config,target,j1..j6 "
                           "(degrees)");
      }
      if (config_col < 0)
        throw InputError({path, line_number, 0, "config"}, "missing column 'config'");
      continue;
    }
    if (cells.size() != header.size())
      throw InputError({path, line_number, 0, ""},
                       fmt::format("expected {} fields as in the header, found {}", header.size(),
                                   cells.size()));
    ConfigurationRow row;
    row.line = line_number;
    PlannedConfiguration& config = row.config;
    config.name = cells[static_cast<size_t>(config_col)];
    if (config.name.empty())
      throw InputError(
          {path, line_number, cell_column(line, static_cast<size_t>(config_col)), "config"},
          "empty configuration label");
    for (int j = 0; j < kJointCount; ++j) {
      const size_t col = static_cast<size_t>(joint_cols[static_cast<size_t>(j)]);
      const SourceLocation where{path, line_number, cell_column(line, col), header[col]};
      size_t used = 0;
      double value = 0;
      try {
        value = std::stod(cells[col], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != cells[col].size() || !std::isfinite(value))
        throw InputError(where,
                         fmt::format("expected a finite angle in degrees, found '{}'", cells[col]));
      // Three turns either way is beyond any joint (robot files allow ±1080°): a typo or a slip.
      if (std::abs(value) > kMaxJointDeg)
        throw InputError(where, fmt::format("{} is outside the plausible range [-{}, {}] deg",
                                            cells[col], kMaxJointDeg, kMaxJointDeg));
      config.joints[j] = deg2rad(value);
    }
    if (target_col >= 0) {
      row.target = cells[static_cast<size_t>(target_col)];
      row.target_at = {path, line_number, cell_column(line, static_cast<size_t>(target_col)),
                       "target"};
    }
    if (approach_col >= 0)
      config.approach = parse_approach(
          cells[static_cast<size_t>(approach_col)],
          {path, line_number, cell_column(line, static_cast<size_t>(approach_col)), "approach"});
    if (payload_col >= 0) {
      row.payload = cells[static_cast<size_t>(payload_col)];
      row.payload_at = {path, line_number, cell_column(line, static_cast<size_t>(payload_col)),
                        "payload"};
    }
    if (const auto [at, added] = first_line.emplace(config.name, line_number); !added)
      throw InputError(
          {path, line_number, cell_column(line, static_cast<size_t>(config_col)), "config"},
          fmt::format("configuration '{}' is listed twice (first on line {})", config.name,
                      at->second));
    largest_deg = std::max(largest_deg, rad2deg(config.joints.cwiseAbs().maxCoeff()));
    configs.push_back(std::move(row));
  }
  if (header.empty()) throw InputError({path, 0, 0, ""}, "empty file: expected a header row");
  if (configs.empty())
    throw InputError({path, line_number, 0, ""}, "no configuration rows after the header");
  // As for measurement files (io/measurement_file.cpp): radians read as degrees would give
  // configurations where the robot barely moves.
  if (configs.size() >= 5 && largest_deg > 0.01 && largest_deg <= 2 * std::numbers::pi + 1e-6)
    throw InputError({path, 0, 0, "j1"},
                     fmt::format("every joint value is within ±{:.3f} over {} rows: they look like "
                                 "radians; a configurations file holds degrees",
                                 largest_deg, configs.size()));
  return configs;
}

std::vector<PlannedConfiguration> read_configurations_csv(const std::string& path,
                                                          const Tool& tool) {
  std::vector<PlannedConfiguration> configs;
  for (ConfigurationRow& row : parse_configuration_rows(read_text_file(path), path)) {
    if (!row.target.empty()) {
      row.config.target = tool.target_index(row.target);
      if (row.config.target < 0) {
        std::string known;
        for (const Target& t : tool.targets) known += (known.empty() ? "" : ", ") + t.name;
        throw InputError(row.target_at,
                         fmt::format("unknown target '{}'; the tool has {}", row.target, known));
      }
    }
    if (!row.payload.empty())
      row.config.payload =
          payload_index_of(row.payload, tool, row.payload_at, "the tool's own payload");
    configs.push_back(std::move(row.config));
  }
  return configs;
}

std::string write_configurations_csv(const std::vector<PlannedConfiguration>& configs,
                                     const Tool& tool) {
  const bool approach = std::any_of(configs.begin(), configs.end(),
                                    [](const auto& c) { return c.approach != Vector6d::Ones(); });
  const bool payload =
      std::any_of(configs.begin(), configs.end(), [](const auto& c) { return c.payload >= 0; });
  std::string out = fmt::format("config,target,j1,j2,j3,j4,j5,j6{}{}\n",
                                approach ? ",approach" : "", payload ? ",payload" : "");
  for (const PlannedConfiguration& c : configs) {
    out += c.name + ",";
    if (c.target >= 0) out += tool.targets.at(static_cast<size_t>(c.target)).name;
    for (int j = 0; j < kJointCount; ++j) out += fmt::format(",{}", rad2deg(c.joints[j]));
    if (approach) out += "," + approach_text(c.approach);
    if (payload)
      out += "," + (c.payload < 0 ? std::string()
                                  : tool.payloads.at(static_cast<size_t>(c.payload)).name);
    out += "\n";
  }
  return out;
}

Eigen::Vector3d world_from_base(const TrueRobot& truth, const Eigen::Vector3d& p_base_mm) {
  return detail::base_transform(truth.robot.params.data(), 0.0, 0.0) * p_base_mm;
}

VirtualInstrument standard_instrument(InstrumentKind kind, const TrueRobot& truth,
                                      double noise_mm) {
  VirtualInstrument instrument;
  instrument.kind = kind;
  instrument.ballbar.nominal_length_mm = 150;
  instrument.ballbar.centre_mm = world_from_base(truth, Eigen::Vector3d(300, 0, 250));
  if (noise_mm > 0) {
    instrument.tracker.sigma_mm.setConstant(noise_mm);
    instrument.cmm.sigma_mm = noise_mm;
    instrument.cmm.sigma_orientation_deg = rad2deg(noise_mm / 100.0);
    instrument.ballbar.sigma_mm = noise_mm;
  }
  return instrument;
}

namespace {

/// The side each joint reaches `joints` from (+1 below, −1 above), the way the true robot's
/// backlash sees it: drawn for `approach_random` (the move then starts 5° away on that side),
/// the configuration's `planned` sides as the measurement program moves, or the direction of
/// the straight move from the previous configuration.
Vector6d approach_to(const Vector6d& joints, const Vector6d& planned,
                     const SimulationOptions& options, std::mt19937_64& sides,
                     MotionState& motion) {
  Vector6d approach = planned;  // as the measurement program moves: 5° away on the planned side
  if (options.approach_random) {
    for (int j = 0; j < kJointCount; ++j) approach[j] = (sides() & 1U) ? 1.0 : -1.0;
  } else if (!options.approach_from_below) {
    for (int j = 0; j < kJointCount; ++j)
      approach[j] = joints[j] < motion.previous_joints[j] ? -1.0 : 1.0;
    return approach;
  }
  motion.previous_joints = joints - deg2rad(5.0) * approach;
  return approach;
}

}  // namespace

SimulationResult simulate_measurements(const TrueRobot& truth, const VirtualInstrument& instrument,
                                       const std::vector<PlannedConfiguration>& configs,
                                       std::mt19937_64& rng, const SimulationOptions& options) {
  SimulationResult result;
  MeasurementSet& set = result.measurements;
  const Tool& tool = truth.robot.tool;
  set.kind = instrument.kind == InstrumentKind::LaserTracker ? MeasurementKind::Points
             : instrument.kind == InstrumentKind::OpticalCmm ? MeasurementKind::Poses
                                                             : MeasurementKind::Distances;
  MotionState motion;
  // The true robot sees each joint's side from the move (previous_joints, set per configuration).
  motion.from_below = false;
  motion.previous_joints = configs.empty() ? Vector6d::Zero() : configs.front().joints;
  std::mt19937_64 sides(options.approach_seed);
  for (size_t k = 0; k < configs.size(); ++k) {
    const PlannedConfiguration& config = configs[k];
    motion.time_s = options.seconds_per_measurement * static_cast<double>(k);
    const Vector6d approach = approach_to(config.joints, config.approach, options, sides, motion);
    motion.payload = config.payload;
    if (options.random_payloads)  // -1: the tool's own payload, else one of its `payloads`
      motion.payload =
          std::uniform_int_distribution<int>(-1, static_cast<int>(tool.payloads.size()) - 1)(rng);
    const Pose<double> flange = true_flange_pose(truth, config.joints, motion);
    motion.previous_joints = config.joints;
    if (config.target >= static_cast<int>(tool.targets.size()))
      throw InputError({"", 0, 0, "target"},
                       fmt::format("configuration {}: target index {} but the tool has {} targets",
                                   config.name, config.target, tool.targets.size()));
    switch (instrument.kind) {
      case InstrumentKind::LaserTracker: {
        const std::vector<int> visible = visible_targets(instrument.tracker, flange, tool);
        int target = config.target;
        if (target < 0 && !visible.empty())
          target = visible[std::uniform_int_distribution<size_t>(0, visible.size() - 1)(rng)];
        if (target < 0 || std::find(visible.begin(), visible.end(), target) == visible.end()) {
          result.skipped.push_back(fmt::format(
              "{}: {} not facing the tracker (SMR cone ±{}°)", config.name,
              target < 0 ? "no target" : "target " + tool.targets[static_cast<size_t>(target)].name,
              instrument.tracker.cone_half_angle_deg));
          continue;
        }
        const Eigen::Vector3d p = flange * tool.targets[static_cast<size_t>(target)].position_mm;
        set.points.push_back({config.name, target, config.joints,
                              read_point(instrument.tracker, p, rng), 0, approach});
        break;
      }
      case InstrumentKind::OpticalCmm: {
        if (!cmm_sees_tool(instrument.cmm, flange, tool)) {
          result.skipped.push_back(fmt::format("{}: no face of the tool within {}° of the camera",
                                               config.name, instrument.cmm.facing_limit_deg));
          continue;
        }
        Pose<double> flange_T_tcp;
        flange_T_tcp.R = tool.flange_T_tcp.linear();
        flange_T_tcp.p = tool.flange_T_tcp.translation();
        set.poses.push_back({config.name, config.joints,
                             read_pose(instrument.cmm, flange * flange_T_tcp, rng), 0, approach});
        break;
      }
      case InstrumentKind::Ballbar: {
        const int target = std::max(config.target, 0);
        const Eigen::Vector3d cup =
            flange * tool.targets.at(static_cast<size_t>(target)).position_mm;
        const std::optional<double> length = read_length(instrument.ballbar, cup, rng);
        if (!length) {
          result.skipped.push_back(
              fmt::format("{}: length {:.3f} mm outside the ballbar's {} ± {} mm", config.name,
                          (cup - instrument.ballbar.centre_mm).norm(),
                          instrument.ballbar.nominal_length_mm, instrument.ballbar.range_mm));
          continue;
        }
        set.distances.push_back({config.name, target, config.joints, *length, 0, approach});
        break;
      }
    }
    set.set_payload(set.size() - 1, motion.payload);
    if (truth.effects.thermal && options.record_time)  // the warm-up group's input (§10)
      set.set_time_s(set.size() - 1, motion.time_s);
    else if (truth.effects.thermal)  // a thermometer on the arm (the thermal group's input, §8)
      set.set_temperature_c(set.size() - 1, truth.robot.model.reference_temperature_c +
                                                temperature_rise(truth.effects, motion.time_s));
  }
  return result;
}

namespace {

/// Moves `joints` so that `target` sits `length` from `centre` on the nominal robot placed
/// like the truth (Gauss-Newton on the scalar length error, minimum-norm joint steps).
bool reach_sphere(const RobotModel& model, const ParameterVector& placed_nominal,
                  const Eigen::Vector3d& target, const Eigen::Vector3d& centre, double length,
                  Vector6d& joints) {
  auto error = [&](const Vector6d& q) {
    return (flange_pose(model, PointMass{}, placed_nominal, q) * target - centre).norm() - length;
  };
  for (int iteration = 0; iteration < 30; ++iteration) {
    const double f = error(joints);
    if (std::abs(f) < 1e-7) return true;
    Vector6d gradient;
    for (int j = 0; j < kJointCount; ++j) {
      Vector6d qp = joints, qm = joints;
      qp[j] += 1e-6;
      qm[j] -= 1e-6;
      gradient[j] = (error(qp) - error(qm)) / 2e-6;
    }
    if (gradient.squaredNorm() < 1e-12) return false;
    joints -= f * gradient / gradient.squaredNorm();
  }
  return false;
}

}  // namespace

std::vector<PlannedConfiguration> random_configurations(const TrueRobot& truth,
                                                        const VirtualInstrument& instrument,
                                                        int count, std::mt19937_64& rng,
                                                        const RandomConfigurationOptions& options) {
  const RobotModel& model = truth.robot.model;
  const Tool& tool = truth.robot.tool;
  const ParameterVector nominal = model.nominal();
  ParameterVector placed_nominal = nominal;
  placed_nominal.head<kBaseParamCount>() = truth.robot.params.head<kBaseParamCount>();
  std::vector<PlannedConfiguration> configs;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int n = 0; n < count; ++n) {
    bool found = false;
    for (int attempt = 0; attempt < options.max_attempts && !found; ++attempt) {
      PlannedConfiguration config;
      config.name = fmt::format("{}{}", options.name_prefix, n + 1);
      for (size_t j = 0; j < kJointCount; ++j)
        config.joints[static_cast<int>(j)] =
            options.box[j].lower + (options.box[j].upper - options.box[j].lower) * unit(rng);
      if (instrument.kind == InstrumentKind::Ballbar) {
        config.target =
            std::uniform_int_distribution<int>(0, static_cast<int>(tool.targets.size()) - 1)(rng);
        if (!reach_sphere(
                model, placed_nominal, tool.targets[static_cast<size_t>(config.target)].position_mm,
                instrument.ballbar.centre_mm, instrument.ballbar.nominal_length_mm, config.joints))
          continue;
        bool inside = true;
        for (size_t j = 0; j < kJointCount; ++j)
          inside = inside && config.joints[static_cast<int>(j)] >= options.box[j].lower &&
                   config.joints[static_cast<int>(j)] <= options.box[j].upper;
        if (!inside) continue;
      }
      // Every target above the base plane (nominal robot, base frame).
      const Pose<double> base_T_flange = flange_pose(model, PointMass{}, nominal, config.joints);
      bool high_enough = true;
      for (const Target& t : tool.targets)
        high_enough =
            high_enough && (base_T_flange * t.position_mm).z() >= options.min_target_height_mm;
      if (!high_enough) continue;
      const Pose<double> flange = true_flange_pose(truth, config.joints);
      switch (instrument.kind) {
        case InstrumentKind::LaserTracker: {
          const std::vector<int> visible = visible_targets(instrument.tracker, flange, tool);
          if (visible.empty()) continue;
          config.target =
              visible[std::uniform_int_distribution<size_t>(0, visible.size() - 1)(rng)];
          break;
        }
        case InstrumentKind::OpticalCmm:
          if (!cmm_sees_tool(instrument.cmm, flange, tool)) continue;
          break;
        case InstrumentKind::Ballbar:
          break;
      }
      if (options.accept && !options.accept(config)) continue;
      configs.push_back(config);
      found = true;
    }
    if (!found)
      throw InputError({"", 0, 0, "--random"},
                       fmt::format("no measurable configuration found in {} random draws for {} "
                                   "(joint box, target height {} mm, what it can see): widen the "
                                   "box or move the instrument",
                                   options.max_attempts, instrument_name(instrument.kind),
                                   options.min_target_height_mm));
  }
  return configs;
}

}  // namespace robcal
