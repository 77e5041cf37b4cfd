#include "robcal/campaign/frames_file.hpp"

#include <fmt/format.h>

#include <map>

#include "robcal/campaign/cell.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"

namespace robcal::campaign {
namespace {

std::string comment_lines(const std::string& comment) {
  std::string out;
  size_t start = 0;
  while (start < comment.size()) {
    const size_t newline = std::min(comment.find('\n', start), comment.size());
    out += "# " + comment.substr(start, newline - start) + "\n";
    start = newline + 1;
  }
  return out;
}

/// "[a, b, c]" with full precision.
std::string list3(double a, double b, double c) {
  return fmt::format("[{}, {}, {}]", a, b, c);
}

std::string position_and_rotation(const FrameEstimate& f) {
  return fmt::format("position_mm: {}, rotation_xyz_deg: {}",
                     list3(f.values[0], f.values[1], f.values[2]),
                     list3(rad2deg(f.values[3]), rad2deg(f.values[4]), rad2deg(f.values[5])));
}

std::string sigma_map(const FrameEstimate& f) {
  return fmt::format("{{position_mm: {}, rotation_xyz_deg: {}}}",
                     list3(f.sigma[0], f.sigma[1], f.sigma[2]),
                     list3(rad2deg(f.sigma[3]), rad2deg(f.sigma[4]), rad2deg(f.sigma[5])));
}

}  // namespace

JointSweep sweep_from_measurements(const MeasurementSet& set, int joint, const RobotModel& model) {
  if (set.kind != MeasurementKind::Points)
    throw InputError({set.file, 0, 0, ""},
                     fmt::format("a sweep is a points file (config,target,j1..j6,x,y,z); this is "
                                 "a {} file",
                                 measurement_kind_name(set.kind)));
  JointSweep sweep;
  sweep.joint = joint;
  if (set.points.empty()) throw InputError({set.file, 0, 0, ""}, "no readings in the sweep");
  const auto first = model_joint_angles(model, set.points.front().joints.data());
  for (const PointMeasurement& m : set.points) {
    if (m.target != set.points.front().target)
      throw InputError({set.file, m.line, 0, "target"},
                       "a sweep follows one target: this row reads another one than the first row");
    const auto q = model_joint_angles(model, m.joints.data());
    for (int j = 0; j < kJointCount; ++j)
      if (j != joint - 1 && std::abs(q[j] - first[j]) > 1e-9)
        throw InputError(
            {set.file, m.line, 0, fmt::format("j{}", j + 1)},
            fmt::format("joint {} moved ({:.6f}° vs {:.6f}° on line {}, model "
                        "angles): only joint {} may turn in this sweep",
                        j + 1, rad2deg(q[j]), rad2deg(first[j]), set.points.front().line, joint));
    sweep.joints.push_back(m.joints);
    sweep.points_mm.push_back(m.position_mm);
  }
  return sweep;
}

PointEstimate tool_point_from_measurements(const RobotModel& model, const ParameterVector& params,
                                           const MeasurementSet& set, double sigma_mm) {
  if (set.kind != MeasurementKind::Points || set.points.empty())
    throw InputError({set.file, 0, 0, ""}, "expected a points file (config,target,j1..j6,x,y,z)");
  std::vector<Pose<double>> flanges;
  std::vector<Eigen::Vector3d> measured;
  for (const PointMeasurement& m : set.points) {
    if (m.target != set.points.front().target)
      throw InputError({set.file, m.line, 0, "target"},
                       "the rows must all read one target (the first row's)");
    flanges.push_back(flange_pose(model, PointMass{}, params, m.joints));
    measured.push_back(m.position_mm);
  }
  try {
    return tool_point_from_poses(flanges, measured, sigma_mm);
  } catch (const InputError& e) {
    throw InputError({set.file, 0, 0, ""}, e.what());
  }
}

std::string robot_base_block(const FrameEstimate& base) {
  return fmt::format(
      "robot_base:\n"
      "  position_mm: {}\n"
      "  rotation_xyz_deg: {}\n"
      "  source: measured\n"
      "  sigma: {}\n",
      list3(base.values[0], base.values[1], base.values[2]),
      list3(rad2deg(base.values[3]), rad2deg(base.values[4]), rad2deg(base.values[5])),
      sigma_map(base));
}

std::string cell_with_base(const std::string& cell_text, const std::string& cell_file,
                           const FrameEstimate& base, const std::string& comment) {
  // The block runs from the `robot_base:` line to the next line that starts a top-level key
  // (or a top-level comment, which belongs to what follows).
  size_t start = std::string::npos;
  for (size_t pos = 0; pos < cell_text.size();) {
    if (cell_text.compare(pos, 11, "robot_base:") == 0) {
      start = pos;
      break;
    }
    const size_t newline = cell_text.find('\n', pos);
    pos = newline == std::string::npos ? cell_text.size() : newline + 1;
  }
  if (start == std::string::npos)
    throw InputError({cell_file, 0, 0, "robot_base"},
                     "no top-level 'robot_base:' line to replace (a cell file has one)");
  size_t end = cell_text.find('\n', start);
  while (end != std::string::npos && end + 1 < cell_text.size() &&
         (cell_text[end + 1] == ' ' || cell_text[end + 1] == '\t' || cell_text[end + 1] == '\n'))
    end = cell_text.find('\n', end + 1);
  end = end == std::string::npos ? cell_text.size() : end + 1;
  std::string out = cell_text.substr(0, start) + comment_lines(comment) + robot_base_block(base) +
                    cell_text.substr(end);
  parse_cell(out, cell_file);
  return out;
}

std::string frame_yaml(const std::string& key, const FrameEstimate& frame,
                       const std::string& comment) {
  return comment_lines(comment) +
         fmt::format("{}: {{{}, sigma: {}, sigma_noise_mm: {}, rms_mm: {}}}\n", key,
                     position_and_rotation(frame), sigma_map(frame), frame.sigma_mm, frame.rms_mm);
}

std::vector<NamedPoint> read_named_points(const NamedText& file) {
  const TextTable table = read_text_table(file.text, file.name);
  std::vector<NamedPoint> points;
  for (size_t r = 0; r < table.rows.size(); ++r) {
    const TextRow& row = table.rows[r];
    if (row.fields.size() != 4)
      throw InputError({file.name, row.line, 0, ""},
                       fmt::format("expected 4 fields (name, x, y, z), got {}", row.fields.size()));
    if (r == 0 && row.fields[1].size() == 1 && (row.fields[1] == "x" || row.fields[1] == "X"))
      continue;  // the header
    Eigen::Vector3d p;
    for (size_t k = 0; k < 3; ++k)
      p[static_cast<Eigen::Index>(k)] = parse_number(
          row.fields[k + 1], table.dialect.decimal,
          field_location(table, row, k + 1, std::string(1, static_cast<char>('x' + k))),
          "a coordinate in mm");
    points.push_back({row.fields[0], p, row.line});
  }
  return points;
}

FrameEstimate frame_from_named_nests(const NamedText& measured, const NamedText& nominal,
                                     double sigma_mm) {
  const auto m = read_named_points(measured);
  const auto n = read_named_points(nominal);
  std::map<std::string, const NamedPoint*> by_name;
  for (const NamedPoint& p : n)
    if (!by_name.emplace(p.name, &p).second)
      throw InputError({nominal.name, p.line, 0, p.name},
                       fmt::format("nest '{}' is listed twice (first on line {})", p.name,
                                   by_name.at(p.name)->line));
  std::vector<Eigen::Vector3d> a, b;
  for (const NamedPoint& p : m) {
    const auto it = by_name.find(p.name);
    if (it == by_name.end())
      throw InputError({measured.name, p.line, 0, p.name},
                       fmt::format("nest '{}' is not in {}", p.name, nominal.name));
    a.push_back(p.position_mm);
    b.push_back(it->second->position_mm);
  }
  return frame_from_nests(a, b, sigma_mm);
}

}  // namespace robcal::campaign
