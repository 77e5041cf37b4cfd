// Python bindings of the programs stage (include/robcal/programs/): reading a program's points,
// filtering a program text with a calibrated model (compensate_program_text), writing and reading
// back measurement programs. Degrees and mm outside.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "module_registry.hpp"
#include "py_compensator.hpp"
#include "py_measurements.hpp"
#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/programs/frames_file.hpp"
#include "robcal/programs/measurement_program.hpp"
#include "robcal/programs/program_compensation.hpp"

namespace py = pybind11;

namespace robcal::python {
namespace {

std::optional<std::array<double, kJointCount>> pulses_of(const std::optional<Vector6d>& ppd) {
  if (!ppd) return std::nullopt;
  std::array<double, kJointCount> out{};
  for (int j = 0; j < kJointCount; ++j) out[static_cast<size_t>(j)] = (*ppd)[j];
  return out;
}

const bool registered = register_bindings(71, [](py::module_& m) {
  m.def(
      "read_program_points",
      [](const std::string& text, const std::string& language, bool joints,
         const std::optional<Vector6d>& ppd) {
        ProgramFilterOptions options;
        options.joints = joints;
        if (ppd) options.pulses_per_degree = *pulses_of(ppd);
        py::list out;
        for (const ProgramPoint& p : read_program_points(
                 text, program_language_from_name(language, "language"), "<text>", options)) {
          py::dict d = p.is_joint_target ? py::dict() : pose_dict(p.base_T_tcp);
          d["name"] = p.name;
          d["line"] = p.line;
          d["column"] = p.column;
          d["joint_target"] = p.is_joint_target;
          if (p.is_joint_target) d["joints_deg"] = Vector6d(p.joints_deg);
          d["config"] = p.config;
          d["tool"] = p.tool;
          d["frame"] = p.frame;
          out.append(d);
        }
        return out;
      },
      py::arg("text"), py::arg("language"), py::arg("joints") = false,
      py::arg("pulses_per_degree") = py::none(),
      "Every point of a program ('rapid', 'krl', 'ls', 'jbi', 'urscript'), in file order");

  m.def(
      "filter_program",
      [](const PyCompensator& compensator, const std::string& text, const std::string& language,
         bool joints, bool keep_going, const std::optional<std::string>& frames,
         const std::string& file, const std::optional<Vector6d>& ppd,
         const std::optional<std::string>& dat, const std::string& dat_file) {
        ProgramFilterOptions options;
        options.joints = joints;
        options.keep_going = keep_going;
        if (ppd) options.pulses_per_degree = *pulses_of(ppd);
        if (frames) {
          FramesFile f = read_frames_file(*frames);
          options.tools = std::move(f.tools);
          options.frames = std::move(f.frames);
        }
        const ProgramLanguage lang = program_language_from_name(language, "language");
        if (dat && lang != ProgramLanguage::Krl)
          throw InputError({file, 0, 0, "dat"}, "a .dat text goes with a KRL program only");
        const ProgramCompensationResult r =
            dat ? compensate_krl_module_text(compensator.c, text, *dat, file, dat_file, options)
                : compensate_program_text(compensator.c, text, lang, file, options);
        py::dict d = json_to_python(nlohmann::json(r));
        d["text"] = r.filter.text;
        if (r.filter.dat_text) d["dat_text"] = *r.filter.dat_text;
        d["confidence_csv"] = r.filter.confidence_csv;
        return d;
      },
      py::arg("compensator"), py::arg("text"), py::arg("language"), py::arg("joints") = false,
      py::arg("keep_going") = false, py::arg("frames") = py::none(), py::arg("file") = "<text>",
      py::arg("pulses_per_degree") = py::none(), py::arg("dat") = py::none(),
      py::arg("dat_file") = "<dat>",
      "Corrects every target of a program text with a Compensator (the `robcal "
      "compensate-program` summary, plus the corrected 'text' and 'confidence_csv'). KRL: with "
      "`dat`, the .src text and its .dat corrected together as a module ('dat_text')");

  m.def(
      "write_measurement_program",
      [](const std::string& language, const std::vector<std::string>& names,
         const Eigen::MatrixXd& joints_deg, const std::string& name, const std::string& hook,
         int signal, double settle_s, double approach_deg, double speed_percent,
         int max_configs_per_file, int tool_number, const std::optional<Vector6d>& ppd,
         const std::optional<std::string>& robot, const std::string& date,
         const std::optional<std::vector<bool>>& approach,
         const std::optional<std::vector<bool>>& measure) {
        if (joints_deg.cols() != kJointCount ||
            joints_deg.rows() != static_cast<Eigen::Index>(names.size()))
          throw InputError({"<arrays>", 0, 0, "joints_deg"},
                           "expected one row of six joints (deg) per name");
        for (const auto& [flags, key] : {std::pair{&approach, "approach"}, {&measure, "measure"}})
          if (*flags && (*flags)->size() != names.size())
            throw InputError({"<arrays>", 0, 0, key}, "expected one flag per name");
        MeasurementProgramRequest r;
        r.language = program_language_from_name(language, "language");
        r.names = names;
        for (Eigen::Index i = 0; i < joints_deg.rows(); ++i)
          r.joints.emplace_back(joints_deg.row(i).transpose() * kDegToRad);
        r.name = name;
        r.hook = measurement_hook_from_name(hook, "hook");
        r.signal = signal;
        r.settle_s = settle_s;
        r.approach_deg = approach_deg;
        r.joint_speed_percent = speed_percent;
        r.max_configs_per_file = max_configs_per_file;
        r.tool_number = tool_number;
        r.pulses_per_degree = pulses_of(ppd);
        if (robot) r.limits = load_robot(*robot).limits;
        r.date = date;
        if (approach || measure)
          for (size_t i = 0; i < names.size(); ++i) {
            ConfigurationVisit& visit = r.visits.emplace_back();
            visit.approach = approach ? (*approach)[i] : true;
            visit.measure = measure ? (*measure)[i] : true;
          }
        py::list out;
        for (const ProgramFile& f : write_measurement_program(r)) {
          py::dict d;
          d["name"] = f.name;
          d["text"] = f.text;
          out.append(d);
        }
        return out;
      },
      py::arg("language"), py::arg("names"), py::arg("joints_deg"), py::arg("name") = "RCMEAS",
      py::arg("hook") = "wait", py::arg("signal") = 1, py::arg("settle_s") = 1.0,
      py::arg("approach_deg") = 5.0, py::arg("speed_percent") = 10.0,
      py::arg("max_configs_per_file") = 0, py::arg("tool_number") = 1,
      py::arg("pulses_per_degree") = py::none(), py::arg("robot") = py::none(),
      py::arg("date") = "2000/01/01 00:00", py::arg("approach") = py::none(),
      py::arg("measure") = py::none(),
      "The measurement program visiting each configuration (N×6 joints, deg) from q - "
      "approach_deg, as `robcal program`: a list of {'name', 'text'} files. `approach` and "
      "`measure` (one bool per name): the joint approach and the settle wait + hook of each "
      "configuration (false: a pass-through pose such as an ISO 9283 vAP pre-pose)");

  m.def(
      "write_measurement_program_files",
      [](const std::string& language, const std::string& configs, const std::string& out_dir,
         const std::optional<std::string>& robot, const std::optional<std::string>& tool,
         const std::string& name, const std::string& hook, double approach_deg,
         const std::optional<Vector6d>& ppd, const std::string& date) {
        MeasurementProgramFilesRequest request;
        request.program.language = program_language_from_name(language, "language");
        request.program.name = name;
        request.program.hook = measurement_hook_from_name(hook, "hook");
        request.program.approach_deg = approach_deg;
        request.program.pulses_per_degree = pulses_of(ppd);
        request.program.date = date;
        request.configs = configs;
        request.robot = robot.value_or("");
        request.tool = tool.value_or("");
        request.out_dir = out_dir;
        return write_measurement_program_from_files(request).paths;
      },
      py::arg("language"), py::arg("configs"), py::arg("out_dir"), py::arg("robot") = py::none(),
      py::arg("tool") = py::none(), py::arg("name") = "RCMEAS", py::arg("hook") = "wait",
      py::arg("approach_deg") = 5.0, py::arg("pulses_per_degree") = py::none(),
      py::arg("date") = "2000/01/01 00:00",
      "`robcal program`: reads the configurations CSV (what `robcal plan` writes), checks them "
      "against the robot's limits and writes the program's files into out_dir; their paths");

  m.def(
      "read_joint_moves",
      [](const std::string& text, const std::string& language, const std::optional<Vector6d>& ppd) {
        const std::vector<JointMove> moves = read_joint_moves(
            text, program_language_from_name(language, "language"), "<text>", pulses_of(ppd));
        Eigen::MatrixXd joints(static_cast<Eigen::Index>(moves.size()), kJointCount);
        std::vector<int> lines;
        for (size_t i = 0; i < moves.size(); ++i) {
          joints.row(static_cast<Eigen::Index>(i)) = moves[i].joints_deg.transpose();
          lines.push_back(moves[i].line);
        }
        py::dict d;
        d["joints_deg"] = joints;
        d["lines"] = lines;
        return d;
      },
      py::arg("text"), py::arg("language"), py::arg("pulses_per_degree") = py::none(),
      "Every absolute joint move of a program text: joints_deg N×6 and their lines");
});

}  // namespace
}  // namespace robcal::python
