#include "robcal/io/robot_file.hpp"
#include "robcal/io/robot_pulses.hpp"

#include <dlfcn.h>
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdlib>
#include <optional>

#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/number_text.hpp"
#include "robcal/io/yaml_checks.hpp"

namespace robcal {

namespace fs = std::filesystem;

namespace {
/// The first `share/robcal/data` in `start`'s folder or one of its parents (a few levels: an
/// executable in <prefix>/bin, a library in <prefix>/lib/<multiarch>, a Python module in
/// <prefix>/lib/python3/dist-packages/robcal, a build tree with its share/robcal/data link).
std::optional<fs::path> data_beside(const fs::path& start) {
  std::error_code ec;
  const fs::path file = fs::canonical(start, ec);
  if (ec) return std::nullopt;
  fs::path dir = file.parent_path();
  for (int level = 0; level < 5 && !dir.empty(); ++level, dir = dir.parent_path()) {
    const fs::path candidate = dir / "share" / "robcal" / "data";
    if (fs::is_directory(candidate / "robots", ec)) return candidate;
    if (dir == dir.root_path()) break;
  }
  return std::nullopt;
}

/// The data folder, or nothing when there is none (see data_directory()).
std::optional<fs::path> find_data_directory() {
  if (const char* env = std::getenv("ROBCAL_DATA_DIR"); env && *env) return fs::path(env);
  // The file holding this code: the shared library, or the program or Python module the static
  // library was linked into; then the running program itself.
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&find_data_directory), &info) != 0 && info.dli_fname)
    if (auto found = data_beside(info.dli_fname)) return found;
  return data_beside("/proc/self/exe");
}
}  // namespace

fs::path data_directory() {
  if (auto found = find_data_directory()) return *found;
  throw InputError({"", 0, 0, "ROBCAL_DATA_DIR"},
                   "cannot find the robot library (share/robcal/data beside the installed program "
                   "or library): set ROBCAL_DATA_DIR to the folder holding robots/");
}

std::vector<std::string> builtin_robot_names() {
  std::vector<std::string> names;
  const auto data = find_data_directory();
  if (!data) return names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(*data / "robots", ec))
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

namespace {

/// The YAML root of a built-in robot by name or of a robot file by path.
yaml::Node robot_file_root(const std::string& name_or_path) {
  if (const auto data = find_data_directory(); data && name_or_path.find('/') == std::string::npos)
    if (const fs::path builtin = *data / "robots" / (name_or_path + ".yaml"); fs::exists(builtin))
      return yaml::load_file(builtin.string());
  if (fs::exists(name_or_path)) {
    // Other robot descriptions are converted first, not misread as a robot file.
    const std::string text = read_text_file(name_or_path);
    const size_t start = text.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
    if (start != std::string::npos && text[start] == '<')
      throw InputError({name_or_path, 0, 0, ""},
                       "an XML file (a URDF?), not a robot file: convert a URDF with `robcal "
                       "model import --urdf FILE --out robot.yaml`");
    if (text.find("opw_kinematics_geometric_parameters") != std::string::npos ||
        text.find("kinematics_solver_geometric_parameters") != std::string::npos)
      throw InputError({name_or_path, 0, 0, ""},
                       "an OPW parameter file (ROS-Industrial), not a robot file: it holds no "
                       "joint limits; convert it with the library's load_opw_robot "
                       "(io/opw_file.hpp) and give the data sheet's limits");
    return yaml::load_file(name_or_path);
  }
  std::string known;
  for (const auto& n : builtin_robot_names()) known += (known.empty() ? "" : ", ") + n;
  throw InputError(
      {"", 0, 0, "--robot"},
      fmt::format("unknown robot '{}': not a built-in robot ({}) nor a file", name_or_path,
                  known.empty() ? "no robot library found: set ROBCAL_DATA_DIR" : known));
}

/// `pulses_per_degree`: six positive numbers; an encoder of up to 2^24 counts per motor turn
/// behind a gear of up to ~400:1 gives at most ~1e7 pulses per degree.
std::array<double, kJointCount> pulses_per_degree(const yaml::Node& root) {
  std::array<double, kJointCount> out{};
  if (!root.has("pulses_per_degree")) return out;
  constexpr yaml::Range kPulsesPerDegree{1e-3, 1e7, "pulses/deg"};
  const auto ppd = yaml::numbers_in(root.at("pulses_per_degree"), kJointCount, kPulsesPerDegree);
  std::copy(ppd.begin(), ppd.end(), out.begin());
  return out;
}

}  // namespace

RobotModel load_robot(const std::string& name_or_path) {
  return parse_robot(robot_file_root(name_or_path));
}

std::array<double, kJointCount> robot_pulses_per_degree(const std::string& name_or_path) {
  return pulses_per_degree(robot_file_root(name_or_path));
}

namespace {

// Plausible values of the files' fields: anything outside is a typo or a unit slip (metres for
// millimetres, radians for degrees), never a real robot. The largest industrial arms reach
// about 4 m and carry about 2.3 t.
constexpr yaml::Range kLengthMm{-20000, 20000, "mm"};
constexpr yaml::Range kAngleDeg{-360, 360, "deg"};
constexpr yaml::Range kJointLimitDeg{-1080, 1080, "deg"};
constexpr yaml::Range kLinkMassKg{0, 10000, "kg"};
constexpr yaml::Range kPayloadKg{0, 5000, "kg"};
constexpr yaml::Range kGravity{-100, 100, "m/s²"};
constexpr yaml::Range kTemperatureC{-50, 150, "°C"};  // workshop to foundry
constexpr yaml::Range kJointMap{-100, 100, ""};
constexpr yaml::Range kUnit{-1.000001, 1.000001, ""};

/// Tool files' digits: 12 significant digits keep a calibrated target to well below a nanometre.
constexpr int kToolDigits = 12;

EulerConvention parse_euler(const yaml::Node& node) {
  const std::string text = node.as_string();
  if (text == "ZYX" || text == "zyx" || text == "ABC") return EulerConvention::ZyxABC;
  if (text == "WPR" || text == "wpr" || text == "XYZ") return EulerConvention::XyzWPR;
  throw node.error(
      fmt::format("unknown Euler convention '{}': expected ZYX (ABB, KUKA) or WPR (Fanuc)", text));
}

}  // namespace

void parse_gravity(const yaml::Node& root, RobotModel& model) {
  const char* keys[3] = {"gravity_m_s2", "gravity_base_m_s2", "mounting_deg"};
  const char* given = nullptr;
  for (const char* key : keys) {
    if (!root.has(key)) continue;
    if (given)
      throw root.at(key).error(
          fmt::format("'{}' and '{}' both give gravity: keep one (gravity_m_s2 in the world frame, "
                      "gravity_base_m_s2 in the robot's base frame, or mounting_deg [rx, ry])",
                      given, key));
    given = key;
  }
  if (root.has("gravity_m_s2")) {
    model.gravity_m_s2 = yaml::vector3_in(root.at("gravity_m_s2"), kGravity);
    model.gravity_in_base = false;
  }
  if (root.has("gravity_base_m_s2")) {
    model.gravity_m_s2 = yaml::vector3_in(root.at("gravity_base_m_s2"), kGravity);
    model.gravity_in_base = true;
  }
  if (root.has("mounting_deg")) {
    const auto tilt = yaml::numbers_in(root.at("mounting_deg"), 2, kAngleDeg);
    // g_base = (Rot_x(rx)·Rot_y(ry))ᵀ · (0, 0, −9.81).
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(deg2rad(tilt[0]), Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(deg2rad(tilt[1]), Eigen::Vector3d::UnitY()))
                                  .toRotationMatrix();
    model.gravity_m_s2 = R.transpose() * Eigen::Vector3d(0, 0, -9.81);
    model.gravity_in_base = true;
  }
}

/// `gear_ratio`: six entries, each a ratio (motor turns per joint turn, 1 to 10,000) or ~ for a
/// joint whose ratio is unknown (0 in the model).
std::array<double, kJointCount> parse_gear_ratios(const yaml::Node& node) {
  constexpr yaml::Range kGearRatio{1, 10000, "motor turns per joint turn"};
  if (!node.node.IsSequence() || node.size() != kJointCount)
    throw node.error("expected 6 entries, each a gear ratio or ~ (unknown)");
  std::array<double, kJointCount> ratios{};
  for (int i = 0; i < kJointCount; ++i)
    if (node.at(i).defined())
      ratios[static_cast<size_t>(i)] = yaml::number_in(node.at(i), kGearRatio);
  return ratios;
}

void emit_gravity(YAML::Emitter& out, const RobotModel& model) {
  out << YAML::Key << (model.gravity_in_base ? "gravity_base_m_s2" : "gravity_m_s2") << YAML::Value
      << YAML::Flow
      << std::vector<double>{model.gravity_m_s2.x(), model.gravity_m_s2.y(),
                             model.gravity_m_s2.z()};
}

RobotModel parse_robot(const yaml::Node& root) {
  yaml::expect_keys(
      root, {"name", "manufacturer", "source", "euler", "mdh", "joint_limits_deg", "masses",
             "gravity_m_s2", "joint_map", "reach_mm", "pulses_per_degree", "gravity_base_m_s2",
             "mounting_deg", "reference_temperature_c", "gear_ratio", "warmup_time_constant_s"});
  RobotModel model;
  model.name = root.at("name").as_string();
  if (root.has("manufacturer")) model.manufacturer = root.at("manufacturer").as_string();
  if (root.has("source")) model.source = root.at("source").as_string();
  if (root.has("reach_mm")) {
    model.reach_mm = root.at("reach_mm").as_double();
    if (model.reach_mm < 0) throw root.at("reach_mm").error("reach must not be negative");
  }
  if (root.has("euler")) model.euler = parse_euler(root.at("euler"));
  pulses_per_degree(root);  // validated here; read by robot_pulses_per_degree (io/robot_pulses.hpp)

  const yaml::Node mdh = root.at("mdh");
  if (!mdh.node.IsSequence() || mdh.size() != kJointCount)
    throw mdh.error("expected 6 rows [alpha_deg, a_mm, theta_offset_deg, d_mm]");
  for (int i = 0; i < kJointCount; ++i) {
    const yaml::Node r = mdh.at(i);
    if (!r.node.IsSequence() || r.size() != 4)
      throw r.error("expected [alpha_deg, a_mm, theta_offset_deg, d_mm]");
    const std::array<double, 4> row{
        yaml::number_in(r.at(0), kAngleDeg), yaml::number_in(r.at(1), kLengthMm),
        yaml::number_in(r.at(2), kAngleDeg), yaml::number_in(r.at(3), kLengthMm)};
    model.mdh[i] = {deg2rad(row[0]), row[1], deg2rad(row[2]), row[3]};
  }
  if (model.mdh[0].alpha != 0.0 || model.mdh[0].a != 0.0)
    throw mdh.at(0).error("link 1 must have alpha = 0 and a = 0 (its placement is the base)");

  const yaml::Node limits = root.at("joint_limits_deg");
  if (!limits.node.IsSequence() || limits.size() != kJointCount)
    throw limits.error("expected 6 pairs [lower, upper] in degrees");
  for (int i = 0; i < kJointCount; ++i) {
    const auto pair = yaml::numbers_in(limits.at(i), 2, kJointLimitDeg);
    if (!(pair[0] < pair[1])) throw limits.at(i).error("lower limit must be below upper limit");
    model.limits[i] = {deg2rad(pair[0]), deg2rad(pair[1])};
  }

  if (root.has("masses")) {
    const yaml::Node masses = root.at("masses");
    for (const std::string& key : masses.keys()) {
      const yaml::Node entry = masses.at(key);
      const std::optional<int64_t> link = parse_integer(key);
      if (!link || *link < 1 || *link > kJointCount)
        throw entry.error(fmt::format("mass key '{}': expected a link number 1..6", key));
      yaml::expect_keys(entry, {"mass_kg", "cog_mm"});
      const double mass = yaml::number_in(entry.at("mass_kg"), kLinkMassKg);
      model.link_masses[*link - 1] = {mass, yaml::vector3_in(entry.at("cog_mm"), kLengthMm)};
    }
  }
  parse_gravity(root, model);
  if (root.has("reference_temperature_c"))
    model.reference_temperature_c =
        yaml::number_in(root.at("reference_temperature_c"), kTemperatureC);

  if (root.has("gear_ratio")) model.gear_ratio = parse_gear_ratios(root.at("gear_ratio"));
  if (root.has("warmup_time_constant_s"))  // a minute to a working week
    model.warmup_time_constant_s =
        yaml::number_in(root.at("warmup_time_constant_s"), {1, 1e6, "s"});

  if (root.has("joint_map")) {
    const yaml::Node map = root.at("joint_map");
    yaml::expect_keys(map, {"matrix", "offset_deg"});
    if (map.has("matrix")) {
      const yaml::Node matrix = map.at("matrix");
      if (!matrix.node.IsSequence() || matrix.size() != kJointCount)
        throw matrix.error("expected 6 rows of 6 numbers");
      for (int i = 0; i < kJointCount; ++i) {
        const auto row = yaml::numbers_in(matrix.at(i), kJointCount, kJointMap);
        for (int j = 0; j < kJointCount; ++j) model.joint_map.matrix(i, j) = row[j];
      }
      if (std::abs(model.joint_map.matrix.determinant()) < 1e-9)
        throw matrix.error("the joint map must be invertible");
    }
    if (map.has("offset_deg")) {
      const auto offset = yaml::numbers_in(map.at("offset_deg"), kJointCount, kAngleDeg);
      for (int i = 0; i < kJointCount; ++i) model.joint_map.offset[i] = deg2rad(offset[i]);
    }
  }
  return model;
}

void emit_robot_fields(YAML::Emitter& out, const RobotModel& model) {
  out << YAML::Key << "name" << YAML::Value << model.name;
  if (!model.manufacturer.empty())
    out << YAML::Key << "manufacturer" << YAML::Value << model.manufacturer;
  if (!model.source.empty()) out << YAML::Key << "source" << YAML::Value << model.source;
  if (model.reach_mm > 0) out << YAML::Key << "reach_mm" << YAML::Value << model.reach_mm;
  out << YAML::Key << "euler" << YAML::Value
      << (model.euler == EulerConvention::ZyxABC ? "ZYX" : "WPR");
  out << YAML::Key << "mdh" << YAML::Comment("alpha_deg, a_mm, theta_offset_deg, d_mm")
      << YAML::Value << YAML::BeginSeq;
  for (const MdhRow& row : model.mdh)
    out << YAML::Flow
        << std::vector<double>{rad2deg(row.alpha), row.a, rad2deg(row.theta_offset), row.d};
  out << YAML::EndSeq;
  out << YAML::Key << "joint_limits_deg" << YAML::Value << YAML::BeginSeq;
  for (const JointLimit& lim : model.limits)
    out << YAML::Flow << std::vector<double>{rad2deg(lim.lower), rad2deg(lim.upper)};
  out << YAML::EndSeq;
  out << YAML::Key << "masses" << YAML::Value << YAML::BeginMap;
  for (int i = 0; i < kJointCount; ++i) {
    const PointMass& m = model.link_masses[i];
    if (m.mass_kg == 0.0) continue;
    out << YAML::Key << std::to_string(i + 1) << YAML::Value << YAML::Flow << YAML::BeginMap
        << YAML::Key << "mass_kg" << YAML::Value << m.mass_kg << YAML::Key << "cog_mm"
        << YAML::Value << YAML::Flow
        << std::vector<double>{m.cog_mm.x(), m.cog_mm.y(), m.cog_mm.z()} << YAML::EndMap;
  }
  out << YAML::EndMap;
  emit_gravity(out, model);
  if (model.reference_temperature_c != RobotModel{}.reference_temperature_c)
    out << YAML::Key << "reference_temperature_c" << YAML::Value << model.reference_temperature_c;
  if (model.warmup_time_constant_s != RobotModel{}.warmup_time_constant_s)
    out << YAML::Key << "warmup_time_constant_s" << YAML::Value << model.warmup_time_constant_s;
  if (model.gear_ratio != RobotModel{}.gear_ratio) {
    out << YAML::Key << "gear_ratio" << YAML::Value << YAML::Flow << YAML::BeginSeq;
    for (const double r : model.gear_ratio) {
      if (r > 0)
        out << r;
      else
        out << YAML::Null;
    }
    out << YAML::EndSeq;
  }
  if (!model.joint_map.is_identity()) {
    out << YAML::Key << "joint_map" << YAML::Value << YAML::BeginMap << YAML::Key << "matrix"
        << YAML::Value << YAML::BeginSeq;
    for (int i = 0; i < kJointCount; ++i) {
      std::vector<double> row(kJointCount);
      for (int j = 0; j < kJointCount; ++j) row[j] = model.joint_map.matrix(i, j);
      out << YAML::Flow << row;
    }
    out << YAML::EndSeq << YAML::Key << "offset_deg" << YAML::Value << YAML::Flow;
    std::vector<double> offset(kJointCount);
    for (int i = 0; i < kJointCount; ++i) offset[i] = rad2deg(model.joint_map.offset[i]);
    out << offset << YAML::EndMap;
  }
}

std::string robot_to_yaml(const RobotModel& model) {
  YAML::Emitter out;
  out.SetDoublePrecision(12);
  out << YAML::BeginMap;
  emit_robot_fields(out, model);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

namespace {

PointMass parse_payload(const yaml::Node& payload) {
  yaml::expect_keys(payload, {"mass_kg", "cog_mm"});
  return {yaml::number_in(payload.at("mass_kg"), kPayloadKg),
          yaml::vector3_in(payload.at("cog_mm"), kLengthMm)};
}

void emit_payload(YAML::Emitter& out, const PointMass& payload) {
  out << YAML::BeginMap << YAML::Key << "mass_kg" << YAML::Value << payload.mass_kg << YAML::Key
      << "cog_mm" << YAML::Value << YAML::Flow
      << std::vector<double>{payload.cog_mm.x(), payload.cog_mm.y(), payload.cog_mm.z()}
      << YAML::EndMap;
}

}  // namespace

Tool parse_tool(const yaml::Node& root) {
  Tool tool;
  if (root.has("payload")) tool.payload = parse_payload(root.at("payload"));
  if (root.has("payloads")) {  // several payloads in one calibration (§7), named by rows
    const yaml::Node payloads = root.at("payloads");
    for (const std::string& name : payloads.keys())
      tool.payloads.push_back({name, parse_payload(payloads.at(name))});
  }
  if (root.has("targets")) {
    const yaml::Node targets = root.at("targets");
    for (const std::string& name : targets.keys()) {
      const yaml::Node entry = targets.get(name);
      Target target{name, Eigen::Vector3d::Zero(), entry.defined()};
      if (target.known) target.position_mm = yaml::vector3_in(entry, kLengthMm);
      tool.targets.push_back(target);
    }
  }
  const yaml::Node tcp_entry = root.get("tcp");
  tool.tcp_given = tcp_entry.node.IsDefined();
  tool.tcp_position_known = tool.tcp_orientation_known = tcp_entry.defined() || !tool.tcp_given;
  if (root.has("tcp")) {
    const yaml::Node tcp = root.at("tcp");
    yaml::expect_keys(tcp, {"position_mm", "quaternion_wxyz"});
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    // `~` for a part: to be identified from pose measurements.
    const auto written_null = [&](const char* key) {
      const yaml::Node part = tcp.get(key);
      return part.node.IsDefined() && part.node.IsNull();
    };
    tool.tcp_position_known = !written_null("position_mm");
    tool.tcp_orientation_known = !written_null("quaternion_wxyz");
    if (tcp.has("position_mm"))
      T.translation() = yaml::vector3_in(tcp.at("position_mm"), kLengthMm);
    if (tcp.has("quaternion_wxyz")) {
      const auto q = yaml::numbers_in(tcp.at("quaternion_wxyz"), 4, kUnit);
      Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
      if (std::abs(quat.norm() - 1.0) > 1e-6)
        throw tcp.at("quaternion_wxyz")
            .error(fmt::format("quaternion must have unit norm, has {:.9f}", quat.norm()));
      T.linear() = quat.normalized().toRotationMatrix();
    }
    tool.flange_T_tcp = T;
  }
  return tool;
}

Tool load_tool(const std::string& path) {
  const yaml::Node root = yaml::load_file(path);
  if (root.defined()) yaml::expect_keys(root, {"payload", "payloads", "targets", "tcp"});
  return parse_tool(root);
}

void emit_tool(YAML::Emitter& out, const Tool& tool) {
  out.SetDoublePrecision(kToolDigits);
  out << YAML::BeginMap;
  out << YAML::Key << "payload" << YAML::Value;
  emit_payload(out, tool.payload);
  if (!tool.payloads.empty()) {
    out << YAML::Key << "payloads" << YAML::Value << YAML::BeginMap;
    for (const NamedPayload& p : tool.payloads) {
      out << YAML::Key << YAML::DoubleQuoted << p.name << YAML::Value;
      emit_payload(out, p.mass);
    }
    out << YAML::EndMap;
  }
  out << YAML::Key << "targets" << YAML::Value << YAML::BeginMap;
  for (const Target& t : tool.targets) {
    out << YAML::Key << YAML::DoubleQuoted << t.name << YAML::Value;
    if (t.known)
      out << YAML::Flow
          << std::vector<double>{t.position_mm.x(), t.position_mm.y(), t.position_mm.z()};
    else
      out << YAML::Null;
  }
  out << YAML::EndMap;
  if (tool.tcp_given || !tool.flange_T_tcp.isApprox(Eigen::Isometry3d::Identity())) {
    const Eigen::Quaterniond q(tool.flange_T_tcp.linear());
    const Eigen::Vector3d p = tool.flange_T_tcp.translation();
    out << YAML::Key << "tcp" << YAML::Value << YAML::BeginMap << YAML::Key << "position_mm"
        << YAML::Value;
    if (tool.tcp_position_known)
      out << YAML::Flow << std::vector<double>{p.x(), p.y(), p.z()};
    else
      out << YAML::Null;
    out << YAML::Key << "quaternion_wxyz" << YAML::Value;
    if (tool.tcp_orientation_known)
      out << YAML::Flow << std::vector<double>{q.w(), q.x(), q.y(), q.z()};
    else
      out << YAML::Null;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

std::string tool_to_yaml(const Tool& tool) {
  YAML::Emitter out;
  emit_tool(out, tool);
  return std::string(out.c_str()) + "\n";
}

}  // namespace robcal
