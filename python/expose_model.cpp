// Python bindings of the inputs a user holds as arrays: the tool (include/robcal/model/tool.hpp,
// its file in io/robot_file.hpp) and the measurements (measure/measurements.hpp, their CSV in
// io/measurement_file.hpp). Each comes from a file, from numpy arrays or from a dict (the same
// fields as its file: a dict is parsed by the file's own reader). Millimetres and degrees.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/io/yaml_support.hpp"
#include "robcal/kinematics/orientation.hpp"

namespace py = pybind11;

namespace robcal::python {

/// A dict given where a file is read: its JSON text is YAML, read by the file's own parser, so the
/// keys and errors are the file's ("<dict> (targets.T1): …").
yaml::Node dict_as_file(const py::dict& d) {
  const std::string text = py::module_::import("json").attr("dumps")(d).cast<std::string>();
  return yaml::parse(text, "<dict>");
}

namespace {

Vector6d row_joints(const Eigen::MatrixXd& joints_deg, Eigen::Index r) {
  Vector6d q;
  for (int j = 0; j < kJointCount; ++j) q[j] = deg2rad(joints_deg(r, j));
  return q;
}

void check_rows(const Eigen::MatrixXd& joints_deg, Eigen::Index n, const char* what) {
  if (joints_deg.cols() != kJointCount || joints_deg.rows() != n)
    throw InputError({"<arrays>", 0, 0, "joints_deg"},
                     std::string("expected N×6 joints (deg) and ") + what + " of N rows");
  if (!joints_deg.allFinite())
    throw InputError({"<arrays>", 0, 0, "joints_deg"}, "expected finite joints");
}

/// No rows yet, of `kind`, from arrays.
Measurements empty_rows(const Tool& tool, MeasurementKind kind) {
  Measurements out{MeasurementSet{}, tool, {}};
  out.set.kind = kind;
  out.set.file = "<arrays>";
  return out;
}

/// The tool's index of row r's target name; InputError naming the row otherwise.
int target_of(const Tool& tool, const std::vector<std::string>& targets, Eigen::Index r) {
  const std::string& name = targets[static_cast<size_t>(r)];
  const int target = tool.target_index(name);
  if (target < 0)
    throw InputError({"<arrays>", static_cast<int>(r) + 1, 0, "targets"},
                     "the tool has no target '" + name + "'");
  return target;
}

Measurements poses_from_arrays(const Tool& tool, const Eigen::MatrixXd& joints_deg,
                               const Eigen::MatrixXd& positions_mm,
                               const Eigen::MatrixXd& quaternions_wxyz) {
  const auto n = positions_mm.rows();
  check_rows(joints_deg, n, "positions_mm (N×3)");
  if (positions_mm.cols() != 3 || quaternions_wxyz.cols() != 4 || quaternions_wxyz.rows() != n)
    throw InputError({"<arrays>", 0, 0, "quaternions_wxyz"},
                     "expected positions_mm N×3 and quaternions_wxyz N×4");
  Measurements out = empty_rows(tool, MeasurementKind::Poses);
  for (Eigen::Index r = 0; r < n; ++r) {
    PoseMeasurement m;
    m.config = std::to_string(r + 1);
    m.joints = row_joints(joints_deg, r);
    m.world_T_tcp = pose_from_position_quaternion(positions_mm.row(r).transpose(),
                                                  quaternions_wxyz.row(r).transpose());
    out.set.poses.push_back(m);
  }
  return out;
}

Measurements distances_from_arrays(const Tool& tool, const Eigen::MatrixXd& joints_deg,
                                   const std::vector<std::string>& targets,
                                   const Eigen::VectorXd& lengths_mm) {
  const auto n = lengths_mm.size();
  check_rows(joints_deg, n, "lengths_mm");
  if (static_cast<Eigen::Index>(targets.size()) != n || !lengths_mm.allFinite())
    throw InputError({"<arrays>", 0, 0, "lengths_mm"}, "expected N finite lengths and N targets");
  Measurements out = empty_rows(tool, MeasurementKind::Distances);
  for (Eigen::Index r = 0; r < n; ++r) {
    DistanceMeasurement m;
    m.config = std::to_string(r + 1);
    m.target = target_of(tool, targets, r);
    m.joints = row_joints(joints_deg, r);
    m.length_mm = lengths_mm[r];
    out.set.distances.push_back(m);
  }
  return out;
}

py::dict tool_targets(const Tool& tool) {
  py::dict out;
  for (const Target& t : tool.targets) out[py::str(t.name)] = t.position_mm;
  return out;
}

const bool registered = register_bindings(5, [](py::module_& m) {
  py::class_<Tool>(m, "Tool",
                   "The tool on the flange: named targets (flange frame, mm; unknown ones are "
                   "identified) and the payload. From a tool file, a dict with the file's fields, "
                   "or targets as arrays.")
      .def(py::init([](const std::map<std::string, Eigen::Vector3d>& targets,
                       const std::vector<std::string>& unknown, double mass_kg,
                       const Eigen::Vector3d& cog_mm) {
             Tool t;
             t.payload = {mass_kg, cog_mm};
             for (const auto& [name, p] : targets) {
               if (!p.allFinite())
                 throw InputError({"<arrays>", 0, 0, "targets." + name}, "expected finite x, y, z");
               t.targets.push_back({name, p, true});
             }
             for (const std::string& name : unknown) {
               if (t.target_index(name) >= 0)
                 throw InputError({"<arrays>", 0, 0, "unknown"},
                                  "target '" + name + "' is both known and unknown");
               t.targets.push_back({name, Eigen::Vector3d::Zero(), false});
             }
             if (t.targets.empty())
               throw InputError({"<arrays>", 0, 0, "targets"}, "expected at least one target");
             return t;
           }),
           py::arg("targets") = std::map<std::string, Eigen::Vector3d>{},
           py::arg("unknown") = std::vector<std::string>{}, py::arg("mass_kg") = 0.0,
           py::arg("cog_mm") = Eigen::Vector3d::Zero().eval(),
           "Targets {name: [x, y, z]} (flange frame, mm) known; `unknown` names targets whose "
           "coordinates calibration identifies; payload mass (kg) and centre of gravity (mm)")
      .def_static("from_file", &load_tool, py::arg("path"), "Reads a tool file (YAML)")
      .def_static(
          "from_dict", [](const py::dict& d) { return parse_tool(dict_as_file(d)); }, py::arg("d"),
          "A tool from a dict with the tool file's fields (errors name the key)")
      .def_property_readonly("targets", &tool_targets,
                             "{name: [x, y, z]} in the flange frame, mm (0 for unknown ones)")
      .def_property_readonly(
          "unknown_targets",
          [](const Tool& t) {
            std::vector<std::string> out;
            for (const Target& target : t.targets)
              if (!target.known) out.push_back(target.name);
            return out;
          },
          "Names of the targets whose coordinates are identified")
      .def_property_readonly(
          "mass_kg", [](const Tool& t) { return t.payload.mass_kg; }, "Payload mass, kg")
      .def_property_readonly(
          "cog_mm", [](const Tool& t) { return Eigen::Vector3d(t.payload.cog_mm); },
          "Payload centre of gravity in the flange frame, mm")
      .def("to_yaml", &tool_to_yaml, "The tool file's text")
      .def("__repr__", [](const Tool& t) {
        std::string names;
        for (const Target& target : t.targets)
          names += (names.empty() ? "" : ", ") + target.name + (target.known ? "" : "?");
        return "<Tool targets [" + names + "], payload " + std::to_string(t.payload.mass_kg) +
               " kg>";
      });

  py::class_<Measurements>(m, "Measurements",
                           "Measured rows of one kind (points, poses or distances) with the tool "
                           "they refer to. From a measurement CSV, numpy arrays or a dict.")
      .def_static(
          "from_file",
          [](const std::string& path, const Tool& tool) {
            MeasurementFile file = read_measurements_csv(path, tool);
            return Measurements{std::move(file.measurements), tool, std::move(file.warnings)};
          },
          py::arg("path"), py::arg("tool"), "Reads a measurement CSV (any kind)")
      .def_static("points", &points_from_arrays, py::arg("tool"), py::arg("joints_deg"),
                  py::arg("targets"), py::arg("positions_mm"),
                  "Point rows: joints N×6 (deg), target names (N), positions N×3 (mm)")
      .def_static("poses", &poses_from_arrays, py::arg("tool"), py::arg("joints_deg"),
                  py::arg("positions_mm"), py::arg("quaternions_wxyz"),
                  "Pose rows of the TCP: joints N×6 (deg), positions N×3 (mm), unit quaternions "
                  "N×4 (w, x, y, z)")
      .def_static("distances", &distances_from_arrays, py::arg("tool"), py::arg("joints_deg"),
                  py::arg("targets"), py::arg("lengths_mm"),
                  "Ballbar rows: joints N×6 (deg), target names (N), lengths (N, mm)")
      .def_static(
          "from_dict",
          [](const py::dict& d, const Tool& tool) {
            const std::string kind = d.contains("kind") ? d["kind"].cast<std::string>() : "";
            const auto array = [&](const char* key) {
              if (!d.contains(key))
                throw InputError({"<dict>", 0, 0, key}, "missing key for " + kind + " rows");
              return d[key].cast<Eigen::MatrixXd>();
            };
            const auto names = [&] {
              if (!d.contains("target"))
                throw InputError({"<dict>", 0, 0, "target"}, "missing key for " + kind + " rows");
              return d["target"].cast<std::vector<std::string>>();
            };
            if (kind == "points")
              return points_from_arrays(tool, array("joints_deg"), names(), array("position_mm"));
            if (kind == "poses")
              return poses_from_arrays(tool, array("joints_deg"), array("position_mm"),
                                       array("quaternion_wxyz"));
            if (kind == "distances")
              return distances_from_arrays(tool, array("joints_deg"), names(),
                                           array("length_mm").reshaped());
            throw InputError({"<dict>", 0, 0, "kind"},
                             "expected 'points', 'poses' or 'distances', got '" + kind + "'");
          },
          py::arg("d"), py::arg("tool"), "Rows from a dict as to_dict() returns it")
      .def_property_readonly(
          "kind",
          [](const Measurements& s) { return std::string(measurement_kind_name(s.set.kind)); },
          "'points', 'poses' or 'distances'")
      .def_readonly("tool", &Measurements::tool, "The tool the targets refer to")
      .def_readonly("warnings", &Measurements::warnings, "Ignored columns of the file")
      .def("to_dict", &measurements_dict,
           "kind, config, target (points/distances), joints_deg (N×6), position_mm (N×3) and "
           "quaternion_wxyz (poses), length_mm (distances), warnings")
      .def(
          "to_csv", [](const Measurements& s) { return write_measurements_csv(s.set, s.tool); },
          "The measurement file's text (reads back to the same numbers)")
      .def("__len__", [](const Measurements& s) { return s.set.size(); })
      .def("__repr__", [](const Measurements& s) {
        return "<Measurements " + std::to_string(s.set.size()) + " " +
               std::string(measurement_kind_name(s.set.kind)) + " rows from " + s.set.file + ">";
      });
});

}  // namespace

Measurements points_from_arrays(const Tool& tool, const Eigen::MatrixXd& joints_deg,
                                const std::vector<std::string>& targets,
                                const Eigen::MatrixXd& positions_mm) {
  const auto n = positions_mm.rows();
  check_rows(joints_deg, n, "positions_mm (N×3)");
  if (positions_mm.cols() != 3 || static_cast<Eigen::Index>(targets.size()) != n ||
      !positions_mm.allFinite())
    throw InputError({"<arrays>", 0, 0, "positions_mm"},
                     "expected N finite rows x, y, z (mm) and N target names");
  Measurements out = empty_rows(tool, MeasurementKind::Points);
  for (Eigen::Index r = 0; r < n; ++r) {
    out.set.points.push_back({std::to_string(r + 1), target_of(tool, targets, r),
                              row_joints(joints_deg, r), positions_mm.row(r).transpose(), 0});
  }
  return out;
}

py::dict measurements_dict(const Measurements& measurements) {
  const MeasurementSet& set = measurements.set;
  const Tool& tool = measurements.tool;
  const auto n = static_cast<Eigen::Index>(set.size());
  py::list configs, targets;
  Eigen::MatrixXd joints(n, kJointCount);
  py::dict d;
  d["kind"] = std::string(measurement_kind_name(set.kind));
  const auto add_row = [&](Eigen::Index r, const std::string& config, const Vector6d& q) {
    configs.append(config);
    for (int j = 0; j < kJointCount; ++j) joints(r, j) = rad2deg(q[j]);
  };
  if (set.kind == MeasurementKind::Poses) {
    Eigen::MatrixXd position(n, 3), quaternion(n, 4);
    for (Eigen::Index r = 0; r < n; ++r) {
      const PoseMeasurement& m = set.poses[static_cast<size_t>(r)];
      add_row(r, m.config, m.joints);
      position.row(r) = m.world_T_tcp.p.transpose();
      const Eigen::Quaterniond q = to_quaternion(m.world_T_tcp.R);
      quaternion.row(r) << q.w(), q.x(), q.y(), q.z();
    }
    d["position_mm"] = position;
    d["quaternion_wxyz"] = quaternion;
  } else if (set.kind == MeasurementKind::Points) {
    Eigen::MatrixXd position(n, 3);
    for (Eigen::Index r = 0; r < n; ++r) {
      const PointMeasurement& m = set.points[static_cast<size_t>(r)];
      add_row(r, m.config, m.joints);
      targets.append(tool.targets[static_cast<size_t>(m.target)].name);
      position.row(r) = m.position_mm.transpose();
    }
    d["position_mm"] = position;
    d["target"] = targets;
  } else {
    Eigen::VectorXd length(n);
    for (Eigen::Index r = 0; r < n; ++r) {
      const DistanceMeasurement& m = set.distances[static_cast<size_t>(r)];
      add_row(r, m.config, m.joints);
      targets.append(tool.targets[static_cast<size_t>(m.target)].name);
      length[r] = m.length_mm;
    }
    d["length_mm"] = length;
    d["target"] = targets;
  }
  d["config"] = configs;
  d["joints_deg"] = joints;
  d["warnings"] = measurements.warnings;
  return d;
}

}  // namespace robcal::python
