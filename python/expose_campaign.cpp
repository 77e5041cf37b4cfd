// Python bindings of the measurement campaign (include/robcal/campaign/: import, frames, the
// guided session's journal) and of the demo (include/robcal/sim/demo_workflow.hpp). Files in,
// or numpy arrays in; the CLI's JSON documents and numpy arrays out. mm and degrees.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <optional>

#include "module_registry.hpp"
#include "py_measurements.hpp"
#include "py_session_io.hpp"
#include "robcal/campaign/frames_workflow.hpp"
#include "robcal/campaign/import_workflow.hpp"
#include "robcal/campaign/point_session.hpp"
#include "robcal/campaign/session_workflow.hpp"
#include "robcal/core/error.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/sim/demo_workflow.hpp"
#include "robcal/sim/simulator.hpp"
#include "robcal/sim/true_robot.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

Eigen::VectorXd as_vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

/// The rows of an N×3 array (mm).
std::vector<Eigen::Vector3d> points_of(const Eigen::MatrixXd& rows, const char* name) {
  if (rows.cols() != 3) throw InputError({"<arrays>", 0, 0, name}, "expected N×3 (mm)");
  std::vector<Eigen::Vector3d> out;
  for (Eigen::Index r = 0; r < rows.rows(); ++r) out.emplace_back(rows.row(r).transpose());
  return out;
}

campaign::JointSweep sweep_of(int joint, const Eigen::MatrixXd& joints_deg,
                              const Eigen::MatrixXd& points_mm, const char* name) {
  if (joints_deg.cols() != kJointCount || joints_deg.rows() != points_mm.rows())
    throw InputError({"<arrays>", 0, 0, name},
                     "expected N×6 joints (deg) and N×3 points (mm) with the same N");
  campaign::JointSweep sweep{joint, {}, points_of(points_mm, name)};
  for (Eigen::Index r = 0; r < joints_deg.rows(); ++r) {
    Vector6d q;
    for (int i = 0; i < kJointCount; ++i) q[i] = deg2rad(joints_deg(r, i));
    sweep.joints.push_back(q);
  }
  return sweep;
}

py::dict frame_dict(const campaign::FrameEstimate& frame) {
  py::dict d = json_to_python(campaign::frame_estimate_json(frame));
  d["covariance"] = Eigen::MatrixXd(frame.covariance);  // mm, rad
  return d;
}

py::dict target_dict(const std::string& target, const campaign::PointEstimate& point) {
  py::dict d = json_to_python(campaign::target_estimate_json(target, point));
  d["covariance"] = Eigen::MatrixXd(point.covariance);  // mm²
  return d;
}

/// A target estimate with the tool file to write.
py::dict target_file_dict(const campaign::TargetFrameResult& r) {
  py::dict d = target_dict(r.target, r.point);
  d["text"] = r.text;
  return d;
}

/// The guided session's state outside the CLI's prompt loop: the steps of a plan, the readings
/// answered so far (replayed from a journal or added), and what they give.
struct PointSession {
  campaign::SessionSettings settings;
  std::vector<campaign::SessionStep> steps;
  std::vector<campaign::SessionReading> readings;

  const campaign::SessionStep& next(const char* what) const {
    if (readings.size() >= steps.size())
      throw InputError({"<session>", 0, 0, what}, "every step is answered");
    return steps[readings.size()];
  }
  std::string add(campaign::SessionReading reading) {
    readings.push_back(std::move(reading));
    return campaign::journal_line(readings.back());
  }
};

py::dict step_dict(const campaign::SessionStep& s) {
  py::dict d;
  d["key"] = s.key;
  d["prompt"] = s.prompt;
  d["config"] = s.config;
  d["drift_check"] = s.drift_check;
  return d;
}

void expose_session(py::module_& m) {
  py::class_<PointSession>(m, "PointSession",
                           "The guided tracker/CMM session without its prompt loop: the steps of "
                           "a plan, readings replayed from a journal or added, the result")
      .def(py::init([](const std::string& configs, const std::optional<Tool>& tool, int reference,
                       int every) {
             PointSession s;
             s.settings.tool = tool.value_or(default_simulation_tool());
             s.settings.configs = read_configurations_csv(configs, s.settings.tool);
             s.settings.reference = reference;
             s.settings.every = every;
             s.steps = campaign::session_steps(s.settings);
             return s;
           }),
           py::arg("configs"), py::arg("tool") = py::none(), py::arg("reference") = -1,
           py::arg("every") = 0,
           "From a plan file (config,target,j1..j6 in deg), the tool (default: the simulator's), "
           "the reference configuration's index (-1: none) and the drift-check period")
      .def_property_readonly(
          "steps",
          [](const PointSession& s) {
            py::list out;
            for (const campaign::SessionStep& step : s.steps) out.append(step_dict(step));
            return out;
          },
          "[{'key', 'prompt', 'config', 'drift_check'}] in the order they are asked")
      .def_property_readonly(
          "answered", [](const PointSession& s) { return s.readings.size(); },
          "Steps answered so far")
      .def_property_readonly(
          "next_step",
          [](const PointSession& s) -> py::object {
            if (s.readings.size() >= s.steps.size()) return py::none();
            return step_dict(s.steps[s.readings.size()]);
          },
          "The next step to answer, or None when the session is complete")
      .def(
          "replay",
          [](PointSession& s, const std::string& text, const std::string& file) {
            size_t complete = 0;
            s.readings = campaign::replay_journal(text, file, s.steps, &complete);
            return complete;
          },
          py::arg("text"), py::arg("file") = "<journal>",
          "Replaces the readings by a journal's (its text): returns the length of its complete "
          "lines (a torn last line is dropped); raises InputError for a journal of another plan")
      .def(
          "load_journal",
          [](PointSession& s, const std::string& path) {
            s.readings = campaign::replay_journal(read_text_file(path), path, s.steps);
            return s.readings.size();
          },
          py::arg("path"), "Resumes from a journal file: returns the steps answered")
      .def(
          "answer",
          [](PointSession& s, const std::string& line, const std::string& time) {
            return s.add(campaign::parse_answer(line, s.next("answer"), time));
          },
          py::arg("line"), py::arg("time") = "",
          "Answers the next step as the operator types it ('x y z [°C]' or 'skip'); returns the "
          "journal line to append")
      .def(
          "add_reading",
          [](PointSession& s, const std::optional<Eigen::Vector3d>& position_mm,
             const std::string& time, std::optional<double> temperature_c) {
            return s.add({s.next("add_reading").key, position_mm, time, temperature_c});
          },
          py::arg("position_mm"), py::arg("time") = "", py::arg("temperature_c") = py::none(),
          "Answers the next step with a reading (None: marked missing); returns the journal line")
      .def(
          "journal",
          [](const PointSession& s) {
            std::string text;
            for (const campaign::SessionReading& r : s.readings) text += campaign::journal_line(r);
            return text;
          },
          "The journal's text for the readings so far")
      .def(
          "result",
          [](const PointSession& s) {
            const campaign::SessionResult r =
                campaign::session_result(s.settings, s.steps, s.readings);
            py::dict out = json_to_python(campaign::session_result_json(r));
            out["measurements"] = Measurements{r.measurements, s.settings.tool, {}};
            return out;
          },
          "{'measurements': Measurements, 'read', 'missing': [config…], 'drift': [{'key', "
          "'drift_mm', 'time', 'temperature_c'}]} of the readings so far");

  m.def(
      "point_session",
      [](const std::string& configs, const std::string& journal, const std::string& out,
         const std::optional<std::vector<std::string>>& answers, const std::string& tool,
         const std::string& reference, int every, bool resume, const std::string& follow,
         const std::string& map, double follow_timeout_s, const std::string& world_frame) {
        ListedAnswers operator_side{answers.value_or(std::vector<std::string>{})};
        const campaign::SessionIo io = operator_side.io();
        const campaign::PointSessionRun run = [&] {
          py::gil_scoped_release release;
          return campaign::run_point_session({configs, tool, journal, resume, reference, every,
                                              follow, map, follow_timeout_s, out, world_frame},
                                             io);
        }();
        py::dict d = json_to_python(campaign::point_session_json(run));
        d["measurements"] = Measurements{run.result.measurements, run.tool, {}};
        d["csv"] = run.csv;
        d["transcript"] = operator_side.transcript;
        d["refused"] = operator_side.refused;
        return d;
      },
      py::arg("configs"), py::arg("journal"), py::arg("out"), py::arg("answers") = py::none(),
      py::arg("tool") = "", py::arg("reference") = "", py::arg("every") = 0,
      py::arg("resume") = false, py::arg("follow") = "", py::arg("map") = "",
      py::arg("follow_timeout_s") = 600.0, py::arg("world_frame") = "",
      "`robcal session`: the guided session on files, its answers (lines 'x y z [°C]' or "
      "'skip') from `answers` or, with `follow`, from an instrument export as it grows; every "
      "reading journalled at once, `resume` continues a journal. {'status': complete or "
      "paused-…, 'steps', 'answered', 'resumed', 'configurations', 'read', 'missing', 'drift', "
      "'measurements' (Measurements, instrument frame), 'csv' (the file written to `out` when "
      "complete, in the world frame with `world_frame`), 'transcript' (the prompts), 'refused' "
      "(answers asked again)}");
}

const bool registered = register_bindings(90, [](py::module_& m) {
  m.def(
      "demo",
      [](const std::string& out, uint64_t seed, int count, int validation) {
        const DemoResult result = [&] {
          py::gil_scoped_release release;
          return run_demo({out, seed, count, validation});
        }();
        py::dict d = json_to_python(demo_json(result));
        py::dict measured, truth;
        const CampaignResult& c = result.campaign;
        measured["nominal"] = as_vector(c.nominal_vs_measurements.errors_mm);
        truth["nominal"] = as_vector(c.nominal_vs_truth.errors_mm);
        for (const LevelOutcome& level : c.levels) {
          measured[py::str(level_name(level.level))] = as_vector(level.vs_measurements.errors_mm);
          truth[py::str(level_name(level.level))] = as_vector(level.vs_truth.errors_mm);
        }
        d["errors_mm"] = measured;
        d["errors_vs_truth_mm"] = truth;
        return d;
      },
      py::arg("out") = "", py::arg("seed") = 1, py::arg("count") = 50, py::arg("validation") = 1000,
      "`robcal demo`: the whole method on a virtual IRB 120 with a simulated tracker; the CLI's "
      "--json summary plus each model's per-row validation errors (mm) against the readings "
      "(errors_mm) and the truth (errors_vs_truth_mm); writes the folder `out` when given");

  m.def(
      "import_measurements",
      [](const std::string& export_path, const std::string& joints, const std::string& map,
         const std::string& join, double time_tolerance, const std::string& target,
         const std::string& delimiter, const std::string& decimal, const std::string& columns,
         const std::string& unit, const std::string& config_column, bool allow_unmeasured,
         const std::string& world_frame, const std::string& configs) {
        campaign::ImportResult r = campaign::import_files({export_path,
                                                           joints,
                                                           map,
                                                           {{"delimiter", delimiter},
                                                            {"decimal", decimal},
                                                            {"columns", columns},
                                                            {"config-column", config_column},
                                                            {"unit", unit}},
                                                           join,
                                                           time_tolerance,
                                                           target,
                                                           allow_unmeasured,
                                                           world_frame,
                                                           configs});
        py::dict d = json_to_python(campaign::import_json(r));
        d["csv"] = r.csv;
        d["measurements"] = Measurements{std::move(r.measurements), r.targets, r.warnings};
        return d;
      },
      py::arg("export"), py::arg("joints"), py::arg("map") = "", py::arg("join") = "order",
      py::arg("time_tolerance") = 0.5, py::arg("target") = "", py::arg("delimiter") = "",
      py::arg("decimal") = "", py::arg("columns") = "", py::arg("unit") = "",
      py::arg("config_column") = "", py::arg("allow_unmeasured") = false,
      py::arg("world_frame") = "", py::arg("configs") = "",
      "`robcal import`: an instrument export joined with the joint log; {'rows', 'kind', "
      "'warnings', 'csv' (the measurement file's text), 'measurements' (Measurements)}; with "
      "world_frame (a `robcal frames world` file) the positions in that frame and "
      "'world_frame'; with configs (the plan's configurations file) each row's approach and "
      "payload from its configuration there");

  m.def(
      "frames_base",
      [](const std::string& robot, const std::string& joint1, const std::string& joint2,
         const std::string& target, const std::string& cell, double sigma_mm) {
        const campaign::BaseFrameResult r =
            campaign::frames_base({robot, joint1, joint2, target, cell, sigma_mm});
        py::dict d;
        d["base"] = frame_dict(r.base);
        d["text"] = r.text;
        return d;
      },
      py::arg("robot"), py::arg("joint1"), py::arg("joint2"), py::arg("target") = "1",
      py::arg("cell") = "", py::arg("sigma_mm") = 0.0,
      "`robcal frames base` from the points files of a joint-1 and a joint-2 sweep: {'base': "
      "the frame ± σ with its 6×6 covariance (mm, rad), 'text': the cell file (or robot_base "
      "block) to write}");
  m.def(
      "frames_tool",
      [](const std::string& robot, const std::string& joint5, const std::string& joint6,
         const std::string& target, const std::string& tool, double sigma_mm) {
        return target_file_dict(
            campaign::frames_tool({robot, joint5, joint6, "", target, tool, sigma_mm}));
      },
      py::arg("robot"), py::arg("joint5"), py::arg("joint6"), py::arg("target") = "1",
      py::arg("tool") = "", py::arg("sigma_mm") = 0.0,
      "`robcal frames tool` from the points files of a joint-5 and a joint-6 sweep: the target "
      "in the flange frame ± σ, its covariance, 'text': the tool file to write");
  m.def(
      "frames_point",
      [](const std::string& robot, const std::string& cell, const std::string& measurements,
         const std::string& target, const std::string& tool, double sigma_mm) {
        return target_file_dict(
            campaign::frames_point({robot, measurements, "", cell, target, tool, sigma_mm}));
      },
      py::arg("robot"), py::arg("cell"), py::arg("measurements"), py::arg("target") = "1",
      py::arg("tool") = "", py::arg("sigma_mm") = 0.0,
      "`robcal frames point`: the target from ≥ 4 measured configurations with the cell's base");
  m.def(
      "frames_world",
      [](const std::string& measured, const std::string& nominal, double sigma_mm) {
        const campaign::NestFrameResult r = campaign::frames_world({measured, nominal, sigma_mm});
        py::dict d = json_to_python(campaign::nest_frame_json(r));
        d["frame"] = frame_dict(r.frame);
        d["text"] = r.text;
        return d;
      },
      py::arg("measured"), py::arg("nominal"), py::arg("sigma_mm") = 0.0,
      "`robcal frames world` from nest files (name,x,y,z mm): the nests' frame in the "
      "instrument frame ± σ, the instrument in that frame, 'text': the frame block to write");

  m.def(
      "base_from_sweeps",
      [](const RobotModel& robot, const Eigen::MatrixXd& joint1_deg,
         const Eigen::MatrixXd& points1_mm, const Eigen::MatrixXd& joint2_deg,
         const Eigen::MatrixXd& points2_mm, double sigma_mm) {
        return frame_dict(
            campaign::base_from_sweeps(robot, sweep_of(1, joint1_deg, points1_mm, "joint1"),
                                       sweep_of(2, joint2_deg, points2_mm, "joint2"), sigma_mm));
      },
      py::arg("robot"), py::arg("joint1_deg"), py::arg("points1_mm"), py::arg("joint2_deg"),
      py::arg("points2_mm"), py::arg("sigma_mm") = 0.0,
      "frames_base from arrays: each sweep's controller joints N×6 (deg) and measured points "
      "N×3 (mm)");
  m.def(
      "tool_from_sweeps",
      [](const RobotModel& robot, const Eigen::MatrixXd& joint5_deg,
         const Eigen::MatrixXd& points5_mm, const Eigen::MatrixXd& joint6_deg,
         const Eigen::MatrixXd& points6_mm, double sigma_mm) {
        return target_dict("", campaign::tool_from_sweeps(
                                   robot, sweep_of(5, joint5_deg, points5_mm, "joint5"),
                                   sweep_of(6, joint6_deg, points6_mm, "joint6"), sigma_mm));
      },
      py::arg("robot"), py::arg("joint5_deg"), py::arg("points5_mm"), py::arg("joint6_deg"),
      py::arg("points6_mm"), py::arg("sigma_mm") = 0.0,
      "frames_tool from arrays: the target in the flange frame from joint-5 and joint-6 sweeps");
  m.def(
      "frame_from_nests",
      [](const Eigen::MatrixXd& measured_mm, const Eigen::MatrixXd& nominal_mm, double sigma_mm) {
        return frame_dict(campaign::frame_from_nests(
            points_of(measured_mm, "measured_mm"), points_of(nominal_mm, "nominal_mm"), sigma_mm));
      },
      py::arg("measured_mm"), py::arg("nominal_mm"), py::arg("sigma_mm") = 0.0,
      "frames_world from arrays: nests measured (N×3, instrument frame) and their coordinates "
      "(N×3) in the frame to set up, same order");

  expose_session(m);
});

}  // namespace
}  // namespace robcal::python
