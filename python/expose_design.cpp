// Python bindings of the configuration design (include/robcal/design/): observability
// indices and D-optimal selection on a stacked, column-scaled Jacobian given as a matrix, and the
// `plan` workflow (design/calibration_planning.hpp) with joint arrays in and out.

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>
#include <random>

#include "module_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/core/units.hpp"
#include "robcal/design/calibration_planning.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/plan_report.hpp"
#include "robcal/design/selection.hpp"
#include "robcal/identify/calibrated_robot.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

py::dict indices_dict(const ObservabilityIndices& o) {
  py::dict d;
  d["O1"] = o.O1;
  d["O2"] = o.O2;
  d["O3"] = o.O3;
  d["O4"] = o.O4;
  d["O5"] = o.O5;
  return d;
}

/// A design matrix from user rows (already scaled): `rows_per_candidate` rows per candidate.
DesignMatrix design_from(const Eigen::MatrixXd& rows, int rows_per_candidate) {
  if (rows_per_candidate != 1 && rows_per_candidate != 3 && rows_per_candidate != 6)
    throw py::value_error("rows_per_candidate must be 1, 3 or 6");
  if (rows.rows() == 0 || rows.rows() % rows_per_candidate != 0)
    throw py::value_error("the number of rows must be a positive multiple of rows_per_candidate");
  if (!rows.allFinite()) throw py::value_error("the Jacobian has a NaN or infinite entry");
  DesignMatrix d;
  d.rows_per_candidate = rows_per_candidate;
  d.rows = rows;
  d.column_scale = Eigen::VectorXd::Ones(rows.cols());
  for (int j = 0; j < rows.cols(); ++j) d.parameters.push_back(j);
  return d;
}

const bool registered = register_bindings(60, [](py::module_& m) {
  m.def(
      "observability_indices",
      [](const Eigen::MatrixXd& jacobian, int configurations) {
        if (configurations <= 0) throw py::value_error("configurations must be positive");
        return indices_dict(observability_indices(jacobian, configurations));
      },
      py::arg("jacobian"), py::arg("configurations"),
      "O1…O5 (docs/method/05-observability.md §1) of a column-scaled identification Jacobian of n "
      "configurations");
  m.def(
      "select_d_optimal",
      [](const Eigen::MatrixXd& rows, int rows_per_candidate, int count, int restarts,
         uint64_t seed) {
        return select_d_optimal(design_from(rows, rows_per_candidate), count, {restarts, seed})
            .chosen;
      },
      py::arg("rows"), py::arg("rows_per_candidate"), py::arg("count"), py::arg("restarts") = -1,
      py::arg("seed") = 1,
      "Indices of `count` candidates chosen by the fast D-optimal greedy + exchange; `restarts`\n"
      "more seeded descents (negative: by candidate count, as robcal plan)");
  m.def(
      "select_published_exchange",
      [](const Eigen::MatrixXd& rows, int rows_per_candidate, int count, uint64_t seed) {
        std::mt19937_64 rng(seed);
        return select_published_exchange(design_from(rows, rows_per_candidate), count, rng).chosen;
      },
      py::arg("rows"), py::arg("rows_per_candidate"), py::arg("count"), py::arg("seed"),
      "Indices chosen by the published exchange on O1 (random start of 11), seeded");
  m.def(
      "d_efficiency",
      [](const Eigen::MatrixXd& rows, int rows_per_candidate, const std::vector<int>& subset) {
        const DesignMatrix d = design_from(rows, rows_per_candidate);
        for (int i : subset)
          if (i < 0 || i >= d.candidates()) throw py::index_error("candidate index out of range");
        return d_efficiency(d, subset, d_optimal_continuous(d));
      },
      py::arg("rows"), py::arg("rows_per_candidate"), py::arg("subset"),
      "Certified D-efficiency of a subset against the continuous D-optimum");
  m.def(
      "plan",
      [](const std::string& robot, const std::optional<std::string>& tool,
         const std::string& instrument, const std::string& level, int count, int candidates,
         const std::optional<Eigen::MatrixXd>& candidate_joints_deg, uint64_t seed,
         const std::string& constraints, double floor_mm, double noise_mm,
         const std::string& criterion, bool guard, const std::optional<std::string>& cell,
         const std::optional<Eigen::MatrixXd>& task_joints_deg,
         const std::optional<std::string>& task_box, int task_count,
         const std::optional<std::string>& prior_model, const std::optional<double>& misfit_mm,
         const std::vector<std::string>& identify, const std::string& approach,
         const std::string& payloads) {
        PlanRequest request;
        request.model = load_robot(robot);
        request.tool = tool ? load_tool(*tool) : default_simulation_tool();
        request.instrument = parse_instrument_kind(instrument, "instrument");
        request.level = parse_calibration_level(level);
        request.identify = identify;
        request.approach = parse_condition_variety(approach, "below", "approach");
        request.payloads = parse_condition_variety(payloads, "own", "payloads");
        request.count = count;
        request.candidates = candidates;
        request.seed = seed;
        request.constraints = plan_joint_constraints(request.model, constraints, "constraints");
        request.floor_mm = floor_mm;
        request.noise_mm = noise_mm;
        request.criterion = parse_selection_criterion(criterion, "criterion");
        request.guard.enabled = guard;
        if (cell) request.cell = campaign::load_cell(*cell);
        const auto joints_of = [](const Eigen::MatrixXd& deg, const char* name) {
          if (deg.cols() != kJointCount || !deg.allFinite())
            throw py::value_error(std::string(name) + " must be an N×6 array of finite degrees");
          std::vector<Vector6d> out;
          for (Eigen::Index i = 0; i < deg.rows(); ++i)
            out.push_back(deg.row(i).transpose().unaryExpr([](double d) { return deg2rad(d); }));
          return out;
        };
        if (candidate_joints_deg) {
          for (const Vector6d& q : joints_of(*candidate_joints_deg, "candidate_joints_deg"))
            request.candidate_configurations.push_back(
                {fmt::format("M{}", request.candidate_configurations.size() + 1), q, -1});
          request.candidates_file = "candidate_joints_deg";
        }
        if (task_joints_deg) {
          request.task_configurations = joints_of(*task_joints_deg, "task_joints_deg");
          request.task_configurations_file = "task_joints_deg";
        }
        if (task_box) request.task_box = parse_task_box(*task_box, "task_box");
        request.task_count = task_count;
        if (prior_model) {
          request.prior_model = load_calibrated_robot(*prior_model);
          request.prior_model_file = *prior_model;
        }
        request.misfit_mm = misfit_mm;
        PlanResult r;
        {
          py::gil_scoped_release release;
          r = plan_calibration(request);
        }
        Eigen::MatrixXd joints(static_cast<Eigen::Index>(r.configurations.size()), kJointCount);
        std::vector<int> targets;
        std::vector<std::string> sides, payload_names;
        for (size_t k = 0; k < r.configurations.size(); ++k) {
          const PlannedConfiguration& c = r.configurations[k];
          for (int j = 0; j < kJointCount; ++j)
            joints(static_cast<Eigen::Index>(k), j) = rad2deg(c.joints[j]);
          targets.push_back(c.target);
          sides.push_back(approach_text(c.approach));
          payload_names.push_back(
              c.payload < 0 ? "" : request.tool.payloads[static_cast<size_t>(c.payload)].name);
        }
        py::object out = json_to_python(plan_json(request, r, ""));
        out["joints_deg"] = joints;
        out["targets"] = targets;
        out["approach_sides"] = sides;
        out["payload_names"] = payload_names;
        return out;
      },
      py::arg("robot") = "abb-irb120", py::arg("tool") = py::none(),
      py::arg("instrument") = "laser-tracker", py::arg("level") = "full", py::arg("count") = 40,
      py::arg("candidates") = 5000, py::arg("candidate_joints_deg") = py::none(),
      py::arg("seed") = 1, py::arg("constraints") = "auto", py::arg("floor_mm") = 50.0,
      py::arg("noise_mm") = 0.0, py::arg("criterion") = "default", py::arg("guard") = true,
      py::arg("cell") = py::none(), py::arg("task_joints_deg") = py::none(),
      py::arg("task_box") = py::none(), py::arg("task_count") = 1000,
      py::arg("prior_model") = py::none(), py::arg("misfit_mm") = py::none(),
      py::arg("identify") = std::vector<std::string>{}, py::arg("approach") = "auto",
      py::arg("payloads") = "auto",
      "Choose calibration configurations and predict their accuracy (`robcal plan`): the CLI's "
      "JSON as a dict (indices for the chosen and a random choice, predicted_error_mm over the "
      "task region from instrument noise only, predicted_error_with_misfit_mm when the misfit "
      "is known: prior_model, a calibrated model file with its cross-validation, or misfit_mm) "
      "plus joints_deg (count×6), targets, approach_sides ('+-++++' per configuration) and "
      "payload_names ('' the tool's own) of the chosen configurations; identify adds opt-in "
      "groups to the design, approach/payloads (auto, below/own, varied) vary the conditions");
});

}  // namespace
}  // namespace robcal::python
