// Python bindings of the simulation studies (include/robcal/sim/): the published experiments,
// the Monte Carlo against Cramér–Rao and the planning study. Each returns the dict of the JSON
// that the CLI prints (the same library serializer), without the CLI's wall-clock "seconds".

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>

#include "module_registry.hpp"
#include "robcal/campaign/cell.hpp"
#include "robcal/design/calibration_planning.hpp"
#include "robcal/design/candidates.hpp"
#include "robcal/io/pose_list_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/sim/experiments.hpp"
#include "robcal/sim/monte_carlo_study.hpp"
#include "robcal/sim/plan_study_report.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

const bool registered = register_bindings(80, [](py::module_& m) {
  m.def(
      "experiments",
      [](uint64_t seed, const std::string& out) {
        const nlohmann::json j = [&] {
          py::gil_scoped_release release;
          return out.empty()
                     ? published_experiments_json(run_published_experiments(seed))
                     : published_experiments_run_json(run_published_experiments_files(seed, out));
        }();
        return json_to_python(j);
      },
      py::arg("seed") = 1, py::arg("out") = "",
      "The published simulation experiments (docs/method/11-published-results.md §2, `robcal "
      "experiments`): {seed, calibration_configurations, validation_configurations, "
      "experiments: {a, b, c}}; with `out` (a folder) also timed ('seconds') and written there "
      "as results.json and results.md, as the CLI does");

  m.def(
      "montecarlo",
      [](int runs, int poses, int validation, int threads, uint64_t seed, double noise_mm,
         const std::string& level, bool optimal_plan, const std::string& validation_model) {
        MonteCarloOptions options;
        options.runs = runs;
        options.poses = poses;
        options.validation = validation;
        options.threads = threads;
        options.seed = seed;
        const MonteCarloStudyRequest request = monte_carlo_study_request(
            options, noise_mm, level, optimal_plan ? "optimal" : "random", validation_model);
        MonteCarloStudy study;
        {
          py::gil_scoped_release release;
          study = run_monte_carlo_study(request);
        }
        return json_to_python(monte_carlo_study_json(study));
      },
      py::arg("runs") = 1000, py::arg("poses") = 50, py::arg("validation") = 1000,
      py::arg("threads") = 2, py::arg("seed") = 1, py::arg("noise_mm") = 0.022,
      py::arg("level") = "full", py::arg("optimal_plan") = true,
      py::arg("validation_model") = "first-order",
      "Repeated simulated calibrations of the published IRB 120 against the Cramér–Rao "
      "prediction (`robcal montecarlo`): observed and predicted errors (mm), their ratio");

  m.def(
      "plan_study",
      [](const std::string& robot, const std::optional<std::string>& tool,
         const std::string& instrument, const std::string& level, const std::vector<int>& counts,
         int seeds, uint64_t seed, int candidates, const std::string& constraints, double floor_mm,
         double noise_mm, const std::optional<std::string>& task_box,
         const std::optional<std::string>& task_poses, int task_count, const std::string& criterion,
         bool guard, const std::vector<std::string>& effects,
         const std::optional<std::string>& cell, int prior_count) {
        const RobotModel model = load_robot(robot);
        PlanStudyOptions options;
        options.counts = counts;
        options.seeds = seeds;
        options.seed = seed;
        options.plan.level = parse_calibration_level(level);
        options.plan.candidates = candidates;
        options.plan.constraints = plan_joint_constraints(model, constraints, "constraints");
        options.plan.floor_mm = floor_mm;
        options.instrument = parse_instrument_kind(instrument, "instrument");
        options.noise_mm = noise_mm;
        if (task_box) options.task_box = parse_task_box(*task_box, "task_box");
        if (task_poses) {
          options.task_poses = read_pose_list(*task_poses);
          options.task_poses_file = *task_poses;
        }
        options.task_count = task_count;
        options.criterion = parse_selection_criterion(criterion, "criterion");
        options.guard.enabled = guard;
        options.effects = effects;
        if (cell) options.cell = campaign::load_cell(*cell);
        options.prior_count = prior_count;
        check_plan_study_options(options);
        const Tool t = tool ? load_tool(*tool) : default_simulation_tool();
        PlanStudyResult result;
        {
          py::gil_scoped_release release;
          result = run_plan_study(model, t, options);
        }
        return json_to_python(plan_study_json(result, options));
      },
      py::arg("robot") = "abb-irb120", py::arg("tool") = py::none(),
      py::arg("instrument") = "laser-tracker", py::arg("level") = "full",
      py::arg("counts") = std::vector<int>{15, 20, 30, 40, 60}, py::arg("seeds") = 4,
      py::arg("seed") = 1, py::arg("candidates") = 2000, py::arg("constraints") = "auto",
      py::arg("floor_mm") = 50.0, py::arg("noise_mm") = 0.0, py::arg("task_box") = py::none(),
      py::arg("task_poses") = py::none(), py::arg("task_count") = 200,
      py::arg("criterion") = "default", py::arg("guard") = true,
      py::arg("effects") = std::vector<std::string>{}, py::arg("cell") = py::none(),
      py::arg("prior_count") = 60,
      "Planned against random configurations at several counts over random true robots "
      "(`robcal plan-study`); task_box \"xmin,xmax,ymin,ymax,zmin,zmax\" (mm) or task_poses (a "
      "pose-list file) set the task region; criterion default, d or i; effects outside the "
      "model (backlash, j6-periodic, mass-error, thermal); cell a cell file; prior_count random "
      "configurations of each robot's prior calibration for the misfit-aware prediction (0: "
      "none)");
});

}  // namespace
}  // namespace robcal::python
