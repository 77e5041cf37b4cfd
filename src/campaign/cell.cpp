#include "robcal/campaign/cell.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "robcal/campaign/frames.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/yaml_checks.hpp"
#include "robcal/io/yaml_support.hpp"

namespace robcal::campaign {
namespace {

// Plausible values: a cell is at most a hall (trackers measure up to ~80 m away); beyond that a
// number is a unit slip (µm, metres read as mm) or a typo.
constexpr yaml::Range kWorldMm{-100000, 100000, "mm"};
constexpr yaml::Range kAngleDeg{-360, 360, "deg"};

/// Refuses keys of `node` not in `allowed`, naming the first one and what is allowed.
void only_keys(const yaml::Node& node, const std::set<std::string>& allowed) {
  for (const std::string& key : node.keys())
    if (allowed.count(key) == 0) {
      std::string names;
      for (const std::string& a : allowed) names += (names.empty() ? "" : ", ") + a;
      throw node.get(key).error(fmt::format("unknown key '{}': expected {}", key, names));
    }
}

double positive(const yaml::Node& node, const char* what) {
  const double value = node.as_double();
  if (!(value > 0)) throw node.error(fmt::format("expected {} > 0, got {}", what, value));
  return value;
}

std::vector<Eigen::Vector3d> point_list(const yaml::Node& node) {
  if (!node.node.IsSequence()) throw node.error("expected a list of [x, y, z] points (mm)");
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < node.size(); ++i) points.push_back(yaml::vector3_in(node.at(i), kWorldMm));
  return points;
}

CellInstrument parse_instrument(const yaml::Node& node) {
  CellInstrument in;
  const std::string kind = node.at("kind").as_string();
  if (kind == "laser-tracker")
    in.kind = InstrumentKind::LaserTracker;
  else if (kind == "optical-cmm")
    in.kind = InstrumentKind::OpticalCmm;
  else
    throw node.at("kind").error(
        fmt::format("unknown instrument '{}': expected laser-tracker or optical-cmm", kind));
  std::set<std::string> allowed = {"kind",     "position_mm", "from_nests",
                                   "range_mm", "sigma_mm",    "target_axes_flange"};
  if (in.kind == InstrumentKind::LaserTracker) {
    allowed.insert("cone_half_angle_deg");
  } else {
    allowed.insert(
        {"view_direction", "field_of_view_deg", "facing_limit_deg", "min_visible_targets"});
    in.min_range_mm = 1000;  // C-Track 780 working volume (measure/instrument.hpp)
    in.max_range_mm = 4000;
  }
  only_keys(node, allowed);

  if (node.has("position_mm") == node.has("from_nests"))
    throw node.error("give the instrument's place either as position_mm or as from_nests");
  if (node.has("position_mm")) {
    in.position_mm = yaml::vector3_in(node.at("position_mm"), kWorldMm);
  } else {
    const yaml::Node nests = node.at("from_nests");
    only_keys(nests, {"measured_mm", "world_mm"});
    const auto measured = point_list(nests.at("measured_mm"));
    const auto world = point_list(nests.at("world_mm"));
    if (measured.size() < 3 || measured.size() != world.size())
      throw nests.error(
          fmt::format("expected the same number (≥ 3) of measured and world nests, "
                      "got {} and {}",
                      measured.size(), world.size()));
    try {
      // instrument_T_world from the nests; the instrument sits at its inverse's origin.
      const FrameEstimate frame = frame_from_nests(measured, world);
      in.position_mm = frame.pose.inverse().p;
    } catch (const InputError& e) {
      throw nests.error(e.what());
    }
  }
  if (node.has("range_mm")) {
    const auto range = yaml::numbers_in(node.at("range_mm"), 2, kWorldMm);
    if (!(range[0] >= 0 && range[1] > range[0]))
      throw node.at("range_mm").error("expected [min, max] with 0 ≤ min < max (mm)");
    in.min_range_mm = range[0];
    in.max_range_mm = range[1];
  }
  if (node.has("sigma_mm")) in.sigma_mm = positive(node.at("sigma_mm"), "a noise σ");
  if (node.has("cone_half_angle_deg")) {
    in.cone_half_angle_deg = positive(node.at("cone_half_angle_deg"), "a half-angle");
    if (in.cone_half_angle_deg > 90)
      throw node.at("cone_half_angle_deg").error("expected a half-angle ≤ 90°");
  }
  if (node.has("target_axes_flange")) {
    const yaml::Node axes = node.at("target_axes_flange");
    for (const std::string& name : axes.keys()) {
      const Eigen::Vector3d axis = axes.at(name).as_vector3();
      if (axis.norm() < 1e-9) throw axes.at(name).error("expected a non-zero axis");
      in.target_axes_flange.emplace_back(name, axis.normalized());
    }
  }
  if (node.has("view_direction")) {
    in.view_direction = node.at("view_direction").as_vector3();
    if (in.view_direction.norm() < 1e-9)
      throw node.at("view_direction").error("expected a non-zero direction");
    in.view_direction.normalize();
  }
  if (node.has("field_of_view_deg"))
    in.field_of_view_deg = positive(node.at("field_of_view_deg"), "a half-angle");
  if (node.has("facing_limit_deg"))
    in.facing_limit_deg = positive(node.at("facing_limit_deg"), "a limit");
  if (node.has("min_visible_targets")) {
    in.min_visible_targets = node.at("min_visible_targets").as_int();
    if (in.min_visible_targets < 1)
      throw node.at("min_visible_targets").error("expected at least 1");
  }
  return in;
}

}  // namespace

ParameterVector Cell::robot_params(const RobotModel& model) const {
  ParameterVector params = model.nominal();
  for (int i = 0; i < 6; ++i) params[i] = robot_base[static_cast<size_t>(i)];
  return params;
}

Cell parse_cell(const std::string& yaml_text, const std::string& file) {
  const yaml::Node root = yaml::parse(yaml_text, file);
  if (!root.node.IsMap()) throw root.error("expected a cell file (a map with format: robcal-cell)");
  only_keys(root, {"format", "name", "robot_base", "instrument", "floor_z_mm", "link_radius_mm",
                   "keep_out"});
  if (root.at("format").as_string() != "robcal-cell")
    throw root.at("format").error("expected format: robcal-cell");
  Cell cell;
  cell.file = file;
  if (root.has("name")) cell.name = root.at("name").as_string();

  const yaml::Node base = root.at("robot_base");
  only_keys(base, {"position_mm", "rotation_xyz_deg", "source", "sigma"});
  const Eigen::Vector3d p = yaml::vector3_in(base.at("position_mm"), kWorldMm);
  const Eigen::Vector3d r = yaml::vector3_in(base.at("rotation_xyz_deg"), kAngleDeg);
  for (size_t i = 0; i < 3; ++i) {
    cell.robot_base[i] = p[static_cast<Eigen::Index>(i)];
    cell.robot_base[i + 3] = deg2rad(r[static_cast<Eigen::Index>(i)]);
  }
  if (base.has("source")) {
    const std::string source = base.at("source").as_string();
    if (source != "nominal" && source != "measured")
      throw base.at("source").error(
          fmt::format("unknown source '{}': expected nominal or measured", source));
    cell.base_measured = source == "measured";
  }
  if (base.has("sigma")) only_keys(base.at("sigma"), {"position_mm", "rotation_xyz_deg"});

  const yaml::Node instrument = root.at("instrument");
  cell.instrument = parse_instrument(instrument);
  cell.floor_z_mm =
      root.has("floor_z_mm") ? yaml::number_in(root.at("floor_z_mm"), kWorldMm) : p.z();
  if (root.has("link_radius_mm"))
    cell.link_radius_mm = positive(root.at("link_radius_mm"), "a radius");

  if (root.has("keep_out")) {
    const yaml::Node boxes = root.at("keep_out");
    if (!boxes.node.IsSequence())
      throw boxes.error("expected a list of boxes {name, min_mm, max_mm}");
    for (size_t i = 0; i < boxes.size(); ++i) {
      const yaml::Node b = boxes.at(i);
      only_keys(b, {"name", "min_mm", "max_mm"});
      KeepOutBox box{b.has("name") ? b.at("name").as_string() : fmt::format("box {}", i + 1),
                     yaml::vector3_in(b.at("min_mm"), kWorldMm),
                     yaml::vector3_in(b.at("max_mm"), kWorldMm)};
      if (!(box.min_mm.array() < box.max_mm.array()).all())
        throw b.error(
            fmt::format("keep-out box '{}': expected min_mm < max_mm on every axis", box.name));
      if (box.contains(cell.instrument.position_mm))
        throw b.error(
            fmt::format("the instrument at ({:.1f}, {:.1f}, {:.1f}) mm is inside keep-out "
                        "box '{}': move the instrument or the box",
                        cell.instrument.position_mm.x(), cell.instrument.position_mm.y(),
                        cell.instrument.position_mm.z(), box.name));
      cell.keep_out.push_back(std::move(box));
    }
  }
  if (cell.instrument.position_mm.z() < cell.floor_z_mm)
    throw instrument.error(
        fmt::format("the instrument is {:.1f} mm below the floor (floor_z_mm {:.1f})",
                    cell.floor_z_mm - cell.instrument.position_mm.z(), cell.floor_z_mm));
  return cell;
}

Cell load_cell(const std::string& path) {
  return parse_cell(read_text_file(path), path);
}

}  // namespace robcal::campaign
