#include "robcal/report/report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/histogram.hpp"
#include "robcal/validate/position_error.hpp"

namespace robcal {

namespace {

constexpr int kHistogramBins = 20;

nlohmann::json summary_json(std::span<const double> errors) {
  const ErrorStatistics s = error_statistics(errors);
  return {{"count", s.count},
          {"mean_mm", s.mean},
          {"std_mm", s.std},
          {"mean_plus_3std_mm", s.mean_plus_3std()},
          {"max_mm", s.max}};
}

/// Positions measured in each row (targets for points, TCP for poses), in row order.
std::vector<Eigen::Vector3d> measured_positions(const MeasurementSet& set) {
  std::vector<Eigen::Vector3d> out;
  for (const PointMeasurement& m : set.points) out.push_back(m.position_mm);
  for (const PoseMeasurement& m : set.poses) out.push_back(m.world_T_tcp.p);
  return out;
}

nlohmann::json yaml_node_to_json(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Map: {
      nlohmann::json out = nlohmann::json::object();
      for (const auto& kv : node) out[kv.first.as<std::string>()] = yaml_node_to_json(kv.second);
      return out;
    }
    case YAML::NodeType::Sequence: {
      nlohmann::json out = nlohmann::json::array();
      for (const auto& item : node) out.push_back(yaml_node_to_json(item));
      return out;
    }
    case YAML::NodeType::Scalar: {
      const std::string& text = node.Scalar();
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (!text.empty() && end == text.c_str() + text.size() && std::isfinite(value)) return value;
      if (text == "true" || text == "false") return text == "true";
      return text;
    }
    default:
      return nullptr;
  }
}

std::string html_escape(std::string_view text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

/// JSON to embed in a <script> element: "</" cannot end the element early.
std::string script_safe(const std::string& json_text) {
  std::string out;
  out.reserve(json_text.size());
  for (size_t i = 0; i < json_text.size(); ++i) {
    out += json_text[i];
    if (json_text[i] == '<' && i + 1 < json_text.size() && json_text[i + 1] == '/') out += '\\';
  }
  return out;
}

std::string number(double value, int decimals = 4) {
  return std::isfinite(value) ? fmt::format("{:.{}f}", value, decimals) : "–";
}

std::string summary_rows_html(const nlohmann::json& models) {
  std::string rows;
  for (const auto& m : models) {
    const auto& s = m["summary"];
    rows +=
        fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                    html_escape(m["label"].get<std::string>()), s["count"].get<uint64_t>(),
                    number(s["mean_mm"]), number(s["std_mm"]), number(s["mean_plus_3std_mm"]),
                    number(s["max_mm"]));
  }
  return rows;
}

std::string per_target_html(const nlohmann::json& models) {
  std::string rows;
  for (const auto& m : models)
    for (const auto& t : m["per_target"]) {
      const auto& s = t["summary"];
      rows += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></"
          "tr>\n",
          html_escape(m["label"].get<std::string>()), html_escape(t["target"].get<std::string>()),
          s["count"].get<uint64_t>(), number(s["mean_mm"]), number(s["std_mm"]),
          number(s["mean_plus_3std_mm"]), number(s["max_mm"]));
    }
  return rows;
}

std::string parameters_html(const nlohmann::json& parameters) {
  std::string rows;
  for (const auto& p : parameters) {
    const bool identified = p["status"] == "identified";
    const int decimals = p["unit"] == "rad/N·mm" ? 9 : 5;
    const auto show = [&](const char* key) {
      const double v = p[key].get<double>();
      return decimals == 9 ? fmt::format("{:.4e}", v) : number(v, decimals);
    };
    rows += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        html_escape(p["name"].get<std::string>()), html_escape(p["unit"].get<std::string>()),
        show("nominal"), show("value"), identified ? show("std_dev") : std::string("–"),
        html_escape(p["status"].get<std::string>()), html_escape(p["reason"].get<std::string>()));
  }
  return rows;
}

/// A JSON value as a line of text for the diagnostics table: numbers to 6 significant digits,
/// lists joined by "; " (lists of scalars in parentheses), objects as "key value" pairs.
std::string plain_text(const nlohmann::json& value) {
  if (value.is_number()) return fmt::format("{:.6g}", value.get<double>());
  if (value.is_string()) return value.get<std::string>();
  if (value.is_object()) {
    std::vector<std::string> parts;
    for (const auto& [key, child] : value.items())
      parts.push_back(fmt::format("{} {}", key, plain_text(child)));
    return fmt::format("{}", fmt::join(parts, ", "));
  }
  if (value.is_array()) {
    if (value.empty()) return "none";
    std::vector<std::string> parts;
    for (const auto& item : value) parts.push_back(plain_text(item));
    const bool scalars =
        std::none_of(value.begin(), value.end(), [](const auto& v) { return v.is_structured(); });
    return scalars ? fmt::format("({})", fmt::join(parts, ", "))
                   : fmt::format("{}", fmt::join(parts, "; "));
  }
  return value.dump();
}

void flatten(const nlohmann::json& value, const std::string& prefix, std::string& rows) {
  if (value.is_object()) {
    for (const auto& [key, child] : value.items())
      flatten(child, prefix.empty() ? key : fmt::format("{}.{}", prefix, key), rows);
    return;
  }
  rows += fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", html_escape(prefix),
                      html_escape(plain_text(value)));
}

// The page. Tables are static HTML (readable even without scripts); the charts are drawn by
// Chart.js from the embedded data. Markers: @TITLE@, @SUBTITLE@, @SUMMARY@, @TARGETS@,
// @PARAMETERS@, @DIAGNOSTICS@, @NOTES@, @DATA@, @CHARTJS@.
constexpr std::string_view kPage = R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>@TITLE@</title>
<style>
 body { font-family: system-ui, sans-serif; margin: 1.5em auto; max-width: 1100px; color: #222; }
 h1 { font-size: 1.5em; margin-bottom: 0.2em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
 .sub { color: #666; margin-top: 0; }
 table { border-collapse: collapse; font-size: 0.9em; }
 th, td { border-bottom: 1px solid #ddd; padding: 3px 10px; text-align: right; white-space: nowrap; }
 #parameters td:last-child, #diagnostics td:last-child { white-space: normal; text-align: left; }
 th:first-child, td:first-child, td.l { text-align: left; }
 .charts { display: grid; grid-template-columns: repeat(auto-fit, minmax(320px, 1fr)); gap: 1em; }
 .chart { position: relative; height: 260px; }
 #render-status { font-size: 0.75em; color: #999; }
</style>
</head>
<body>
<h1>@TITLE@</h1>
<p class="sub">@SUBTITLE@</p>
<h2>Absolute position error over the validation configurations (mm)</h2>
<table><thead><tr><th>model</th><th>rows</th><th>mean</th><th>std</th><th>mean + 3 std</th><th>max</th></tr></thead>
<tbody>
@SUMMARY@</tbody></table>
<h2>Error histograms, before and after</h2>
<div class="charts" id="histograms"></div>
<h2>Error against distance to the calibration region</h2>
<div class="chart"><canvas id="distance-chart"></canvas></div>
<h2>Per target</h2>
<table><thead><tr><th>model</th><th class="l">target</th><th>rows</th><th>mean</th><th>std</th><th>mean + 3 std</th><th>max</th></tr></thead>
<tbody>
@TARGETS@</tbody></table>
<h2>Parameters (± one standard deviation)</h2>
<table id="parameters"><thead><tr><th>parameter</th><th class="l">unit</th><th>nominal</th><th>value</th><th>std dev</th><th class="l">status</th><th class="l">reason</th></tr></thead>
<tbody>
@PARAMETERS@</tbody></table>
<h2>Fit diagnostics</h2>
<table id="diagnostics"><tbody>
@DIAGNOSTICS@</tbody></table>
@NOTES@
<p id="render-status" data-status="pending">pending</p>
<script type="application/json" id="report-data">@DATA@</script>
<script>@CHARTJS@</script>
<script>
(function () {
  const status = document.getElementById('render-status');
  const fail = (message) => { status.dataset.status = 'error: ' + message; status.textContent = 'error: ' + message; };
  window.addEventListener('error', (e) => fail(e.message));
  try {
    const report = JSON.parse(document.getElementById('report-data').textContent);
    const colours = ['#c0392b', '#e67e22', '#2980b9', '#27ae60', '#8e44ad'];
    const common = { animation: false, responsive: true, maintainAspectRatio: false };
    const holder = document.getElementById('histograms');
    report.models.forEach((model, k) => {
      const h = model.histogram;
      const width = (h.upper_mm - h.lower_mm) / h.counts.length;
      const labels = h.counts.map((_, i) => (h.lower_mm + (i + 0.5) * width).toPrecision(3));
      const box = document.createElement('div');
      box.className = 'chart';
      const canvas = document.createElement('canvas');
      canvas.id = 'histogram-' + k;
      box.appendChild(canvas);
      holder.appendChild(box);
      new Chart(canvas, {
        type: 'bar',
        data: { labels, datasets: [{ label: model.label + ' (' + model.summary.count + ' rows)',
                                      data: h.counts, backgroundColor: colours[k % colours.length],
                                      barPercentage: 1.0, categoryPercentage: 1.0 }] },
        options: { ...common, scales: { x: { title: { display: true, text: 'position error (mm)' } },
                                        y: { title: { display: true, text: 'configurations' } } } }
      });
    });
    const after = report.models[report.models.length - 1];
    const distances = report.distance_to_calibration_mm;
    const points = distances.map((d, i) => ({ x: d, y: after.errors_mm[i] }));
    new Chart(document.getElementById('distance-chart'), {
      type: 'scatter',
      data: { datasets: [{ label: after.label + ': error against distance to the nearest calibration point',
                           data: points, backgroundColor: '#2980b9', pointRadius: 2 }] },
      options: { ...common, scales: { x: { title: { display: true, text: 'distance to the calibration region (mm)' } },
                                      y: { title: { display: true, text: 'position error (mm)' } } } }
    });
    status.dataset.status = 'rendered';
    status.textContent = 'rendered ' + (report.models.length + 1) + ' charts';
  } catch (err) {
    fail(err.message);
  }
})();
</script>
</body>
</html>
)HTML";

void replace_all(std::string& text, std::string_view key, const std::string& value) {
  for (size_t pos = text.find(key); pos != std::string::npos;
       pos = text.find(key, pos + value.size()))
    text.replace(pos, key.size(), value);
}

}  // namespace

std::vector<ReportParameter> report_parameters(const CalibratedRobot& robot) {
  std::vector<ReportParameter> rows;
  const ParameterVector nominal = robot.model.nominal();
  const auto& table = parameter_table();
  for (int i = 0; i < kParameterCount; ++i) {
    const ParameterStatus status = robot.status[static_cast<size_t>(i)];
    if (status == ParameterStatus::Fixed) continue;
    const double factor = table[static_cast<size_t>(i)].to_external();
    const bool has_covariance = robot.covariance.rows() == kParameterCount;
    rows.push_back(
        {table[static_cast<size_t>(i)].name, table[static_cast<size_t>(i)].unit,
         status_name(status), robot.reason[static_cast<size_t>(i)], nominal[i] * factor,
         robot.params[i] * factor,
         has_covariance ? std::sqrt(std::max(0.0, robot.covariance(i, i))) * factor : 0.0});
  }
  return rows;
}

ModelErrors model_errors(const std::string& label, const CalibratedRobot& robot,
                         const std::vector<MeasurementSet>& validation) {
  ModelErrors out;
  out.label = label;
  for (const MeasurementSet& set : validation) {
    const PositionErrors errors = position_errors(robot, set);
    out.errors_mm.insert(out.errors_mm.end(), errors.position_error_mm.begin(),
                         errors.position_error_mm.end());
    for (const PointMeasurement& m : set.points)
      out.target_of_row.push_back(robot.tool.targets.at(static_cast<size_t>(m.target)).name);
    for (size_t i = 0; i < set.poses.size(); ++i) out.target_of_row.emplace_back("tcp");
  }
  return out;
}

std::vector<double> distance_to_calibration(const std::vector<MeasurementSet>& validation,
                                            const MeasurementSet& calibration) {
  const std::vector<Eigen::Vector3d> anchors = measured_positions(calibration);
  std::vector<double> out;
  for (const MeasurementSet& set : validation)
    for (const Eigen::Vector3d& p : measured_positions(set)) {
      double best = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& a : anchors) best = std::min(best, (p - a).norm());
      out.push_back(anchors.empty() ? 0.0 : best);
    }
  return out;
}

nlohmann::json yaml_to_json(const std::string& yaml_text) {
  if (yaml_text.empty()) return nlohmann::json::object();
  return yaml_node_to_json(YAML::Load(yaml_text));
}

nlohmann::json report_json(const ReportData& data) {
  nlohmann::json out;
  out["title"] = data.title;
  out["robot"] = data.robot;
  out["sources"] = data.sources;
  out["models"] = nlohmann::json::array();
  for (const ModelErrors& m : data.models) {
    nlohmann::json model;
    model["label"] = m.label;
    model["summary"] = summary_json(m.errors_mm);
    // Per target, in order of first appearance.
    std::vector<std::string> names;
    for (const std::string& t : m.target_of_row)
      if (std::find(names.begin(), names.end(), t) == names.end()) names.push_back(t);
    model["per_target"] = nlohmann::json::array();
    for (const std::string& name : names) {
      std::vector<double> errors;
      for (size_t i = 0; i < m.errors_mm.size(); ++i)
        if (m.target_of_row[i] == name) errors.push_back(m.errors_mm[i]);
      model["per_target"].push_back({{"target", name}, {"summary", summary_json(errors)}});
    }
    const double upper =
        m.errors_mm.empty()
            ? 1.0
            : std::max(1e-6, *std::max_element(m.errors_mm.begin(), m.errors_mm.end()));
    const Histogram h = make_histogram(m.errors_mm, kHistogramBins, 0.0, upper * (1 + 1e-9));
    model["histogram"] = {{"lower_mm", h.lower}, {"upper_mm", h.upper}, {"counts", h.counts}};
    model["errors_mm"] = m.errors_mm;
    out["models"].push_back(model);
  }
  out["distance_to_calibration_mm"] = data.distance_to_calibration_mm;
  out["parameters"] = nlohmann::json::array();
  for (const ReportParameter& p : data.parameters)
    out["parameters"].push_back({{"name", p.name},
                                 {"unit", p.unit},
                                 {"status", p.status},
                                 {"reason", p.reason},
                                 {"nominal", p.nominal},
                                 {"value", p.value},
                                 {"std_dev", p.std_dev}});
  out["diagnostics"] = data.diagnostics;
  out["notes"] = data.notes;
  return out;
}

std::string load_chartjs() {
  std::string path = ROBCAL_CHARTJS_PATH;
  if (const char* env = std::getenv("ROBCAL_CHARTJS"); env && *env) path = env;
  if (path.empty() || !std::filesystem::exists(path))
    throw InputError({path, 0, 0, "ROBCAL_CHARTJS"},
                     "the report needs Chart.js, which was not found: install Debian's "
                     "libjs-chart.js (`make deps`, then re-run cmake) or set ROBCAL_CHARTJS to "
                     "chart.min.js");
  return read_text_file(path);
}

std::string report_html(const nlohmann::json& report, std::string_view chartjs) {
  std::string page(kPage);
  const std::string title = html_escape(report["title"].get<std::string>());
  std::string subtitle = html_escape(report["robot"].get<std::string>());
  for (const auto& s : report["sources"]) subtitle += " · " + html_escape(s.get<std::string>());
  std::string diagnostics;
  flatten(report["diagnostics"], "", diagnostics);
  std::string notes;
  for (const auto& n : report["notes"])
    notes += "<p>" + html_escape(n.get<std::string>()) + "</p>\n";
  // The data and the library go in last so that their text is never searched for markers.
  replace_all(page, "@TITLE@", title);
  replace_all(page, "@SUBTITLE@", subtitle);
  replace_all(page, "@SUMMARY@", summary_rows_html(report["models"]));
  replace_all(page, "@TARGETS@", per_target_html(report["models"]));
  replace_all(page, "@PARAMETERS@", parameters_html(report["parameters"]));
  replace_all(page, "@DIAGNOSTICS@", diagnostics);
  replace_all(page, "@NOTES@", notes);
  const size_t data_at = page.find("@DATA@");
  page.replace(data_at, 6, script_safe(report.dump()));
  const size_t chart_at = page.find("@CHARTJS@", data_at);
  page.replace(chart_at, 9, chartjs);
  return page;
}

std::string report_table_text(const nlohmann::json& report) {
  std::string out = fmt::format("{:<28} {:>6} {:>9} {:>9} {:>12} {:>9}\n", "model (mm)", "rows",
                                "mean", "std", "mean+3std", "max");
  for (const auto& m : report["models"]) {
    const auto& s = m["summary"];
    out += fmt::format("{:<28} {:>6} {:>9.4f} {:>9.4f} {:>12.4f} {:>9.4f}\n",
                       m["label"].get<std::string>(), s["count"].get<uint64_t>(),
                       s["mean_mm"].get<double>(), s["std_mm"].get<double>(),
                       s["mean_plus_3std_mm"].get<double>(), s["max_mm"].get<double>());
  }
  return out;
}

}  // namespace robcal
