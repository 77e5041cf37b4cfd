#include "robcal/report/report.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>

#include "robcal/core/error.hpp"
#include "robcal/identify/residuals.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/error_statistics_json.hpp"
#include "robcal/validate/histogram.hpp"
#include "robcal/validate/position_error.hpp"
#include "robcal/validate/validation.hpp"

namespace robcal {

namespace {

constexpr int kHistogramBins = 20;
constexpr size_t kResidualRowsShown = 20;  ///< rows of the residual table on the page

nlohmann::json summary_json(std::span<const double> errors) {
  return error_statistics_json(error_statistics(errors), "mm");
}

/// The rows of several points or poses sets as one set (InputError when the kinds differ).
MeasurementSet joined(const std::vector<MeasurementSet>& sets) {
  MeasurementSet out;
  if (sets.empty()) return out;
  out.kind = sets.front().kind;
  out.file = sets.front().file;
  for (const MeasurementSet& s : sets) {
    if (s.kind != out.kind || s.kind == MeasurementKind::Distances)
      throw InputError({s.file, 0, 0, "--measurements"},
                       "the validation files must be all points or all poses files");
    out.points.insert(out.points.end(), s.points.begin(), s.points.end());
    out.poses.insert(out.poses.end(), s.poses.begin(), s.poses.end());
  }
  return out;
}

/// Summary of a class in `unit`: "no data" for an empty one.
nlohmann::json class_summary_json(const ErrorStatistics& s, std::string_view unit) {
  if (s.count == 0) return {{"count", 0}, {"status", "no data"}};
  return error_statistics_json(s, unit);
}

/// Pair distance errors (absolute and signed); fewer than two rows: {count 0, "no data"}.
nlohmann::json pairs_json(const PairwiseDistanceErrors& pairs) {
  if (pairs.stats.count == 0) return {{"count", 0}, {"status", "no data"}};
  nlohmann::json out = error_statistics_json(pairs.stats, "mm");
  out["signed_mean_mm"] = pairs.signed_mean;
  out["positive_share"] = pairs.positive_share();
  return out;
}

/// Every validation row with its name, target, class and each model's errors.
nlohmann::json rows_json(const ReportData& data) {
  nlohmann::json out = nlohmann::json::array();
  if (data.models.empty()) return out;
  const ModelErrors& last = data.models.back();
  // Names a caller did not fill in (ReportData built by hand) stay empty.
  const auto name = [](const std::vector<std::string>& names, size_t r) {
    return r < names.size() ? names[r] : std::string();
  };
  for (size_t r = 0; r < last.errors_mm.size(); ++r) {
    nlohmann::json row = {{"row", r + 1},
                          {"config", name(last.config_of_row, r)},
                          {"target", name(last.target_of_row, r)},
                          {"class", name(last.class_of_row, r)}};
    row["errors_mm"] = nlohmann::json::array();
    for (const ModelErrors& m : data.models) row["errors_mm"].push_back(m.errors_mm.at(r));
    if (!last.orientation_deg.empty()) {
      row["orientation_deg"] = nlohmann::json::array();
      for (const ModelErrors& m : data.models)
        row["orientation_deg"].push_back(m.orientation_deg.at(r));
    }
    if (r < data.distance_to_calibration_mm.size())
      row["distance_to_calibration_mm"] = data.distance_to_calibration_mm[r];
    out.push_back(row);
  }
  return out;
}

/// The ballbar's length errors by configuration class.
nlohmann::json ballbar_classes_json(const std::vector<ClassTable>& tables) {
  nlohmann::json out = nlohmann::json::array();
  for (const ClassTable& t : tables) {
    nlohmann::json rows = nlohmann::json::array();
    for (const ClassRow& r : t.rows)
      rows.push_back({{"class", r.label}, {"length_mm", class_summary_json(r.position_mm, "mm")}});
    out.push_back({{"table", t.name}, {"rows", rows}});
  }
  return out;
}

/// A round bin width (1, 2, 2.5 or 5 × 10^k) giving about `bins` bins up to `top`.
double round_bin_width(double top, int bins) {
  const double raw = top / bins;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * decade >= raw) return m * decade;
  return 10 * decade;
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

/// The opt-in groups (each parameter's σ is in the parameters table): the Wald statistic of the
/// enabled ones and whether the data need them; the others listed as not enabled.
std::string groups_html(const nlohmann::json& groups) {
  if (groups.is_null() || groups.empty()) return "";
  std::string rows;
  for (const auto& g : groups) {
    const bool enabled = g["enabled"].get<bool>();
    const int identified = g["identified"].get<int>();
    const std::string verdict = !enabled          ? "not enabled"
                                : identified == 0 ? "enabled, nothing identified"
                                : g["significant"].get<bool>()
                                    ? "significant: the robot needs it"
                                    : "not significant: harmless, not needed";
    rows += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        html_escape(g["name"].get<std::string>()), enabled ? std::to_string(identified) : "–",
        enabled && identified > 0 ? number(g["wald"].get<double>(), 2) : std::string("–"),
        enabled && identified > 0 ? fmt::format("{:.2g}", g["p_value"].get<double>())
                                  : std::string("–"),
        verdict);
  }
  return "<section id=\"groups-section\"><h2>Parameter groups (Wald test, significant when p &lt; "
         "0.001)</h2>\n"
         "<table id=\"groups\"><thead><tr><th>group</th><th>identified</th><th>W</th>"
         "<th>p</th><th class=\"l\">verdict</th></tr></thead><tbody>\n" +
         rows + "</tbody></table></section>\n";
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
// Chart.js from the embedded data. Each part is a <section> that prints whole when it fits a
// page, and headings never end a page (break-after: avoid). Markers: @TITLE@, @SUBTITLE@,
// @PROVENANCE@, @SUMMARY@, @ORIENTATION@, @CLASSES@, @RESIDUALS@, @PAIRS@, @CLASS_PAIRS@,
// @TARGETS@, @ISO9283@, @BALLBAR@, @PARAMETERS@, @GROUPS@, @DIAGNOSTICS@, @NOTES@, @DATA@,
// @CHARTJS@.
constexpr std::string_view kPage = R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>@TITLE@</title>
<style>
 body { font-family: system-ui, sans-serif; margin: 1.5em auto; max-width: 1100px; color: #222; }
 h1 { font-size: 1.5em; margin-bottom: 0.2em; } h2 { font-size: 1.15em; margin-top: 1.6em; }
 h3 { font-size: 1em; margin: 0.8em 0 0.3em; }
 .sub { color: #666; margin-top: 0; }
 table { border-collapse: collapse; font-size: 0.9em; margin-bottom: 0.6em; }
 th, td { border-bottom: 1px solid #ddd; padding: 3px 10px; text-align: right; white-space: nowrap; }
 #parameters td:last-child, #diagnostics td:last-child, #provenance td:last-child { white-space: normal; text-align: left; }
 th:first-child, td:first-child, td.l { text-align: left; }
 .nodata { color: #999; font-style: italic; }
 .charts { display: grid; grid-template-columns: repeat(auto-fit, minmax(320px, 1fr)); gap: 1em; }
 .chart { position: relative; height: 260px; }
 .caption { color: #555; font-size: 0.85em; margin: 0.3em 0 0.8em; }
 .hash { font-family: monospace; font-size: 0.85em; word-break: break-all; }
 #render-status { font-size: 0.75em; color: #999; }
 @page { size: A4; margin: 14mm; }
 @media print {
  body { margin: 0; max-width: none; font-size: 10pt; }
  section { break-inside: avoid; }
  section.long { break-inside: auto; }
  h1, h2, h3 { break-after: avoid; break-inside: avoid; }
  tr, .chart { break-inside: avoid; }
  #render-status { display: none; }
 }
</style>
</head>
<body>
<h1>@TITLE@</h1>
<p class="sub">@SUBTITLE@</p>
<section id="provenance-section"><h2>Provenance</h2>
<table id="provenance"><tbody>
@PROVENANCE@</tbody></table></section>
<section><h2>Absolute position error over the validation configurations (mm)</h2>
<table id="summary"><thead><tr><th>model</th><th>rows</th><th>mean</th><th>std</th><th>mean + 3 std</th><th>max</th></tr></thead>
<tbody>
@SUMMARY@</tbody></table>
@ORIENTATION@</section>
<section><h2>Before and after on shared axes</h2>
<div class="chart"><canvas id="cdf-chart"></canvas></div>
<p class="caption">Share of validation rows at or below each position error, every model on one
logarithmic axis; below, each model's histogram on bins of a round width.</p>
<div class="charts" id="histograms"></div></section>
<section class="long" id="classes-section"><h2>Errors by configuration class (mm)</h2>
@CLASSES@</section>
<section><h2>Error against distance to the calibration region</h2>
<div class="chart"><canvas id="distance-chart"></canvas></div>
<p class="caption">Position error of the last model at each validation row against the distance
from its measured position to the nearest calibration position.</p></section>
<section class="long" id="residuals-section"><h2>Residuals per configuration</h2>
@RESIDUALS@</section>
<section><h2>Distance errors over every pair of validation rows (mm)</h2>
@PAIRS@
<div class="charts" id="pair-histograms"></div>
<p class="caption">| |m<sub>i</sub> − m<sub>j</sub>| − |p<sub>i</sub> − p<sub>j</sub>| | over every
pair of rows: no world frame enters; signed mean and share of positive errors above (measured
distance the longer).</p>
@CLASS_PAIRS@</section>
<section><h2>Per target</h2>
<table><thead><tr><th>model</th><th class="l">target</th><th>rows</th><th>mean</th><th>std</th><th>mean + 3 std</th><th>max</th></tr></thead>
<tbody>
@TARGETS@</tbody></table></section>
@ISO9283@@BALLBAR@<section class="long" id="parameters-section"><h2>Parameters (± one standard deviation)</h2>
<table id="parameters"><thead><tr><th>parameter</th><th class="l">unit</th><th>nominal</th><th>value</th><th>std dev</th><th class="l">status</th><th class="l">reason</th></tr></thead>
<tbody>
@PARAMETERS@</tbody></table></section>
@GROUPS@<section class="long"><h2>Fit diagnostics</h2>
<table id="diagnostics"><tbody>
@DIAGNOSTICS@</tbody></table></section>
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
    const colours = ['#c0392b', '#2980b9', '#e67e22', '#27ae60', '#8e44ad'];
    const common = { animation: false, responsive: true, maintainAspectRatio: false };
    let charts = 0;
    const chart = (canvas, config) => { new Chart(canvas, config); charts += 1; };
    const round = (v) => Number(v.toPrecision(3)).toString();
    // Cumulative distributions of every model on one logarithmic error axis.
    const cdf = report.models.map((model, k) => {
      const sorted = model.errors_mm.filter((e) => e > 0).sort((a, b) => a - b);
      return { label: model.label, borderColor: colours[k % colours.length], backgroundColor: colours[k % colours.length],
               showLine: true, pointRadius: 0, borderWidth: 2,
               data: sorted.map((e, i) => ({ x: e, y: 100 * (i + 1) / sorted.length })) };
    });
    chart(document.getElementById('cdf-chart'), {
      type: 'scatter', data: { datasets: cdf },
      options: { ...common, scales: {
        x: { type: 'logarithmic', title: { display: true, text: 'position error (mm, logarithmic)' },
             ticks: { callback: (v) => { const m = v / Math.pow(10, Math.floor(Math.log10(v)) );
                                         return [1, 2, 5].some((d) => Math.abs(m - d) < 1e-6) ? round(v) : ''; } } },
        y: { min: 0, max: 100, title: { display: true, text: 'rows at or below (%)' } } } }
    });
    const bars = (holder, id, h, label, colour, axis, unit) => {
      const width = (h.upper_mm - h.lower_mm) / h.counts.length;
      const labels = h.counts.map((_, i) => round(h.lower_mm + i * width));
      const box = document.createElement('div');
      box.className = 'chart';
      const canvas = document.createElement('canvas');
      canvas.id = id;
      box.appendChild(canvas);
      holder.appendChild(box);
      chart(canvas, {
        type: 'bar',
        data: { labels, datasets: [{ label, data: h.counts, backgroundColor: colour,
                                      barPercentage: 1.0, categoryPercentage: 1.0 }] },
        options: { ...common, scales: { x: { title: { display: true, text: axis + ' (mm, bin lower edge)' } },
                                        y: { title: { display: true, text: unit } } } }
      });
    };
    const holder = document.getElementById('histograms');
    report.models.forEach((model, k) => bars(holder, 'histogram-' + k, model.histogram,
        model.label + ' (' + model.summary.count + ' rows)', colours[k % colours.length], 'position error', 'rows'));
    const pairs = document.getElementById('pair-histograms');
    report.models.forEach((model, k) => { if (model.pairs) bars(pairs, 'pairs-' + k, model.pairs.histogram,
        model.label + ' (' + model.pairs.count + ' pairs)', colours[k % colours.length], 'distance error', 'pairs'); });
    const after = report.models[report.models.length - 1];
    const distances = report.distance_to_calibration_mm;
    const points = distances.map((d, i) => ({ x: d, y: after.errors_mm[i] }));
    chart(document.getElementById('distance-chart'), {
      type: 'scatter',
      data: { datasets: [{ label: after.label + ': error against distance to the nearest calibration point',
                           data: points, backgroundColor: '#2980b9', pointRadius: 2 }] },
      options: { ...common, scales: { x: { title: { display: true, text: 'distance to the calibration region (mm)' } },
                                      y: { title: { display: true, text: 'position error (mm)' } } } }
    });
    status.dataset.status = 'rendered';
    status.textContent = 'rendered ' + charts + ' charts';
  } catch (err) {
    fail(err.message);
  }
})();
</script>
</body>
</html>
)HTML";

/// "no data" in a cell, or the value.
std::string cell(const nlohmann::json& summary, const char* key) {
  if (!summary.contains(key)) return "<td class=\"nodata\">no data</td>";
  return "<td>" + number(summary[key].get<double>()) + "</td>";
}

std::string provenance_html(const nlohmann::json& p) {
  const auto text = [](const nlohmann::json& v) {
    if (v.is_null() || (v.is_string() && v.get<std::string>().empty()))
      return std::string("<span class=\"nodata\">not recorded</span>");
    return html_escape(v.is_string() ? v.get<std::string>() : v.dump());
  };
  std::string rows;
  const auto row = [&](const std::string& key, const std::string& value) {
    rows += fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", key, value);
  };
  row("robcal", text(p["robcal_version"]));
  row("date (UTC)", text(p["date_utc"]));
  row("command", text(p["command_line"]));
  row("robot", text(p["robot"]));
  row("level", text(p["level"]));
  row("instrument", text(p["instrument"]));
  row("instrument σ (mm per axis)", p["instrument_sigma_mm"].is_null()
                                        ? text(p["instrument_sigma_mm"])
                                        : number(p["instrument_sigma_mm"].get<double>()));
  row("seed", text(p["seed"]));
  for (const auto& f : p["files"])
    row(html_escape(f["role"].get<std::string>()), html_escape(f["path"].get<std::string>()) +
                                                       "<br><span class=\"hash\">SHA-256 " +
                                                       f["sha256"].get<std::string>() + "</span>");
  if (p["files"].empty()) row("input files", text(nullptr));
  return rows;
}

std::string orientation_html(const nlohmann::json& models) {
  std::string rows;
  for (const auto& m : models)
    if (m.contains("orientation_deg")) {
      const auto& o = m["orientation_deg"];
      rows += fmt::format("<tr><td>{}</td><td>{}</td>{}{}{}{}</tr>\n",
                          html_escape(m["label"].get<std::string>()), o["count"].get<uint64_t>(),
                          cell(o, "mean_deg"), cell(o, "std_deg"), cell(o, "mean_plus_3std_deg"),
                          cell(o, "max_deg"));
    }
  if (rows.empty()) return "";
  return "<h3>Orientation error (deg)</h3>\n<table id=\"orientation\"><thead><tr><th>model</th>"
         "<th>rows</th><th>mean</th><th>std</th><th>mean + 3 std</th><th>max</th></tr></thead>"
         "<tbody>\n" +
         rows + "</tbody></table>\n";
}

/// One HTML table per class table of the last group (a model, or a model's ballbar errors):
/// rows = classes, for each group the `headers` and the cells `cells` makes of the group's row
/// (group["classes"][t]["rows"][r]); tables `include` rejects are left out.
std::string by_class_html(const nlohmann::json& groups, const std::vector<std::string>& headers,
                          const std::function<bool(const nlohmann::json&)>& include,
                          const std::function<std::string(const nlohmann::json&)>& cells) {
  std::string out;
  const auto& tables = groups.back()["classes"];
  const std::string span =
      fmt::format("<td colspan=\"{}\" class=\"nodata\">no data</td>", headers.size());
  for (size_t t = 0; t < tables.size(); ++t) {
    if (!include(tables[t])) continue;
    out += "<table class=\"classes\"><thead><tr><th>" +
           html_escape(tables[t]["table"].get<std::string>()) + "</th>";
    for (const auto& g : groups)
      out += fmt::format("<th colspan=\"{}\">{}</th>", headers.size(),
                         html_escape(g["label"].get<std::string>()));
    out += "</tr><tr><th></th>";
    for (size_t k = 0; k < groups.size(); ++k)
      for (const std::string& h : headers) out += "<th>" + h + "</th>";
    out += "</tr></thead><tbody>\n";
    for (size_t r = 0; r < tables[t]["rows"].size(); ++r) {
      out += "<tr><td>" + html_escape(tables[t]["rows"][r]["class"].get<std::string>()) + "</td>";
      for (const auto& g : groups)
        out += g["classes"].size() <= t ? span : cells(g["classes"][t]["rows"][r]);
      out += "</tr>\n";
    }
    out += "</tbody></table>\n";
  }
  return out;
}

/// Rows, mean and max (mm) of a class summary (`key` of the row).
std::function<std::string(const nlohmann::json&)> count_mean_max(const char* key) {
  return [key](const nlohmann::json& row) {
    const auto& s = row[key];
    return fmt::format("<td>{}</td>{}{}", s["count"].get<uint64_t>(), cell(s, "mean_mm"),
                       cell(s, "max_mm"));
  };
}

bool every_table(const nlohmann::json& /*table*/) {
  return true;
}

/// Position errors by class: rows = classes, columns = models (rows, mean, max).
std::string classes_html(const nlohmann::json& models) {
  if (models.empty() || models.back()["classes"].empty())
    return "<p class=\"nodata\">no class statistics (no validation rows)</p>\n";
  return by_class_html(models, {"rows", "mean", "max"}, every_table, count_mean_max("position_mm"));
}

/// The configuration classes' pair distance errors: rows = classes, columns = models.
std::string class_pairs_html(const nlohmann::json& models) {
  if (models.empty()) return "";
  const std::string out = by_class_html(
      models, {"pairs", "mean |e|", "signed mean", "positive (%)"},
      [](const nlohmann::json& table) {
        return !table["rows"].empty() && table["rows"][0].contains("pairs");
      },
      [](const nlohmann::json& row) {
        const auto& p = row["pairs"];
        if (p["count"].get<uint64_t>() == 0)
          return std::string("<td>0</td><td colspan=\"3\" class=\"nodata\">no data</td>");
        return fmt::format("<td>{}</td><td>{}</td><td>{}</td><td>{}</td>",
                           p["count"].get<uint64_t>(), number(p["mean_mm"]),
                           number(p["signed_mean_mm"]),
                           number(100 * p["positive_share"].get<double>(), 1));
      });
  if (out.empty()) return "";
  return "<h3>By configuration class (pairs of rows both in the class)</h3>\n" + out;
}

/// The rows of the largest errors of the last model (all rows are in the JSON).
std::string residuals_html(const nlohmann::json& report) {
  const auto& rows = report["rows"];
  const auto& models = report["models"];
  if (rows.empty()) return "<p class=\"nodata\">no data</p>\n";
  std::vector<size_t> order(rows.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto last_error = [&](size_t i) { return rows[i]["errors_mm"].back().get<double>(); };
  const size_t shown = std::min(order.size(), kResidualRowsShown);
  std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(shown), order.end(),
                    [&](size_t a, size_t b) { return last_error(a) > last_error(b); });
  const bool distances = rows[0].contains("distance_to_calibration_mm");
  std::string out =
      "<table id=\"residuals\"><thead><tr><th>row</th><th class=\"l\">config</th>"
      "<th class=\"l\">target</th><th class=\"l\">class</th>";
  for (const auto& m : models) out += "<th>" + html_escape(m["label"].get<std::string>()) + "</th>";
  if (distances) out += "<th>to calibration</th>";
  out += "</tr></thead><tbody>\n";
  for (size_t k = 0; k < shown; ++k) {
    const auto& row = rows[order[k]];
    out += fmt::format(
        "<tr><td>{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td>"
        "<td class=\"l\">{}</td>",
        row["row"].get<size_t>(), html_escape(row["config"].get<std::string>()),
        html_escape(row["target"].get<std::string>()),
        html_escape(row["class"].get<std::string>()));
    for (const auto& e : row["errors_mm"]) out += "<td>" + number(e.get<double>()) + "</td>";
    if (distances)
      out += "<td>" + number(row["distance_to_calibration_mm"].get<double>(), 1) + "</td>";
    out += "</tr>\n";
  }
  return fmt::format(
             "<p class=\"caption\">The {} largest position errors (mm) of {} of {} rows, "
             "largest first; every row with every model's error is in the JSON "
             "(\"rows\").</p>\n",
             shown, html_escape(models.back()["label"].get<std::string>()), rows.size()) +
         out + "</tbody></table>\n";
}

std::string pairs_html(const nlohmann::json& models) {
  std::string rows;
  for (const auto& m : models)
    if (m.contains("pairs")) {
      const auto& p = m["pairs"];
      rows += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></"
          "tr>\n",
          html_escape(m["label"].get<std::string>()), p["count"].get<uint64_t>(),
          number(p["mean_mm"]), number(p["std_mm"]), number(p["max_mm"]),
          number(p["signed_mean_mm"]), number(100 * p["positive_share"].get<double>(), 1));
    }
  if (rows.empty()) return "<p class=\"nodata\">no data</p>\n";
  return "<table id=\"pairs\"><thead><tr><th>model</th><th>pairs</th><th>mean |e|</th><th>std</th>"
         "<th>max</th><th>signed mean</th><th>positive (%)</th></tr></thead><tbody>\n" +
         rows + "</tbody></table>\n";
}

std::string iso9283_html(const nlohmann::json& iso) {
  if (iso.is_null()) return "";
  std::string rows;
  const auto abc = [](const nlohmann::json& p, const char* key) {
    if (!p.contains(key)) return std::string("<td class=\"nodata\">no data</td>");
    return fmt::format("<td>{} / {} / {}</td>", number(p[key][0]), number(p[key][1]),
                       number(p[key][2]));
  };
  for (const auto& p : iso["poses"])
    rows += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td>{}{}{}</tr>\n",
                        p["pose"].get<std::string>(), p["cycles"].get<int>(), number(p["AP_mm"]),
                        number(p["RP_mm"]),
                        p.contains("vAP_mm") ? "<td>" + number(p["vAP_mm"]) + "</td>"
                                             : std::string("<td class=\"nodata\">no data</td>"),
                        abc(p, "AP_abc_deg"), abc(p, "RP_abc_deg"));
  std::string distance;
  if (iso.contains("distance"))
    distance = fmt::format(
        "<p>Distance P2–P4 (clause 7.3): commanded {} mm, AD {} mm, RD ±{} mm "
        "over {} cycles.</p>\n",
        number(iso["distance"]["D_c_mm"]), number(iso["distance"]["AD_mm"]),
        number(iso["distance"]["RD_mm"]), iso["distance"]["cycles"].get<int>());
  return "<section><h2>ISO 9283 pose characteristics</h2>\n<table id=\"iso9283\"><thead><tr>"
         "<th>pose</th><th>cycles</th><th>AP (mm)</th><th>RP (mm)</th><th>vAP (mm)</th>"
         "<th>AP a/b/c (deg)</th><th>RP ±a/b/c (deg)</th></tr></thead><tbody>\n" +
         rows + "</tbody></table>\n" + distance +
         "<p class=\"sub\">ISO 9283:1998 clauses 7.2.1 (AP), 7.2.2 (RP), 7.2.3 (vAP), 7.3 (AD, "
         "RD).</p></section>\n";
}

std::string ballbar_html(const nlohmann::json& ballbar, const nlohmann::json& range) {
  std::string rows;
  for (const auto& b : ballbar)
    rows += fmt::format(
        "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td "
        "class=\"l\">{}</td></tr>\n",
        html_escape(b["label"].get<std::string>()), b["count"].get<uint64_t>(),
        number(b["mean_mm"]), number(b["std_mm"]), number(b["max_mm"]), number(b["signed_mean_mm"]),
        number(100 * b["positive_share"].get<double>(), 1), b["centre"].get<std::string>());
  const std::string classes =
      by_class_html(ballbar, {"rows", "mean", "max"}, every_table, count_mean_max("length_mm"));
  return "<section id=\"ballbar-section\"><h2>Ballbar length errors (mm)</h2>\n<table "
         "id=\"ballbar\"><thead><tr>"
         "<th>model</th><th>rows</th><th>mean |e|</th><th>std</th><th>max</th><th>signed mean</th>"
         "<th>positive (%)</th><th class=\"l\">centre</th></tr></thead><tbody>\n" +
         rows + "</tbody></table>\n" +
         fmt::format(
             "<p class=\"caption\">Every reading within the bar's range {} ± {} mm "
             "(nominal length {}).</p>\n",
             number(range["nominal_length_mm"].get<double>(), 3),
             number(range["range_mm"].get<double>(), 3), range["length"].get<std::string>()) +
         "<h3>Length error by configuration class (mm)</h3>\n" + classes + "</section>\n";
}

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
                         const std::vector<MeasurementSet>& validation,
                         const std::optional<Eigen::Matrix3Xd>& calibration_mm) {
  ModelErrors out;
  out.label = label;
  const MeasurementSet set = joined(validation);
  if (set.size() == 0) return out;
  const ValidationReport report =
      validate_model(robot, set, 2, kDefaultOrientationWeightMm, calibration_mm);
  out.errors_mm = report.positions.position_error_mm;
  for (const PointMeasurement& m : set.points)
    out.target_of_row.push_back(robot.tool.targets.at(static_cast<size_t>(m.target)).name);
  for (size_t i = 0; i < set.poses.size(); ++i) out.target_of_row.emplace_back("tcp");
  for (size_t r = 0; r < set.size(); ++r) {
    out.config_of_row.push_back(set.kind == MeasurementKind::Points ? set.points[r].config
                                                                    : set.poses[r].config);
    out.class_of_row.push_back(arm_config(robot.model, row_joints(set, r)).label());
  }
  out.orientation_deg = report.positions.orientation_error_deg;
  out.classes = report.classes;
  out.pairs = report.distances;
  return out;
}

std::vector<double> distance_to_calibration(const std::vector<MeasurementSet>& validation,
                                            const MeasurementSet& calibration) {
  const MeasurementSet rows = joined(validation);
  if (calibration.size() == 0) return std::vector<double>(rows.size(), 0.0);
  return distance_to_nearest(measured_positions(rows), measured_positions(calibration));
}

nlohmann::json iso9283_json(const Iso9283Result& result) {
  const auto vec = [](const Eigen::Vector3d& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  nlohmann::json out;
  out["poses"] = nlohmann::json::array();
  for (const Iso9283PoseFigures& f : result.poses) {
    nlohmann::json p = {{"pose", fmt::format("P{}", f.pose)},
                        {"cycles", f.cycles},
                        {"AP_mm", f.ap_mm},
                        {"AP_xyz_mm", vec(f.ap_xyz_mm)},
                        {"RP_mm", f.rp_mm},
                        {"l_mean_mm", f.l_mean_mm},
                        {"S_l_mm", f.s_l_mm}};
    if (f.has_orientation) {
      p["AP_abc_deg"] = vec(f.ap_abc_deg);
      p["RP_abc_deg"] = vec(f.rp_abc_deg);
    }
    if (f.vap_mm) p["vAP_mm"] = *f.vap_mm;
    if (f.vap_abc_deg) p["vAP_abc_deg"] = vec(*f.vap_abc_deg);
    out["poses"].push_back(p);
  }
  if (result.distance) {
    const Iso9283DistanceFigures& d = *result.distance;
    out["distance"] = {{"between", "P2-P4"}, {"cycles", d.cycles}, {"D_c_mm", d.commanded_mm},
                       {"AD_mm", d.ad_mm},   {"RD_mm", d.rd_mm},   {"S_D_mm", d.s_d_mm}};
    if (d.has_orientation) {
      out["distance"]["AD_abc_deg"] = vec(d.ad_abc_deg);
      out["distance"]["RD_abc_deg"] = vec(d.rd_abc_deg);
    }
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
    // Bins of a round width so that the axis reads 0, 0.25, 0.5… rather than 0.2379…
    const double largest =
        m.errors_mm.empty()
            ? 1.0
            : std::max(1e-6, *std::max_element(m.errors_mm.begin(), m.errors_mm.end()));
    const double width = round_bin_width(largest, kHistogramBins);
    const int bins = std::max(1, static_cast<int>(std::floor(largest / width)) + 1);
    const Histogram h = make_histogram(m.errors_mm, bins, 0.0, width * bins);
    model["histogram"] = {{"lower_mm", h.lower}, {"upper_mm", h.upper}, {"counts", h.counts}};
    model["errors_mm"] = m.errors_mm;
    if (!m.orientation_deg.empty()) {
      model["orientation_deg"] = error_statistics_json(error_statistics(m.orientation_deg), "deg");
    }
    model["classes"] = nlohmann::json::array();
    for (const ClassTable& t : m.classes) {
      nlohmann::json rows = nlohmann::json::array();
      for (const ClassRow& r : t.rows) {
        nlohmann::json row = {{"class", r.label},
                              {"position_mm", class_summary_json(r.position_mm, "mm")}};
        if (!m.orientation_deg.empty())
          row["orientation_deg"] = class_summary_json(r.orientation_deg, "deg");
        if (r.pairs) row["pairs"] = pairs_json(*r.pairs);
        rows.push_back(row);
      }
      model["classes"].push_back({{"table", t.name}, {"rows", rows}});
    }
    if (m.pairs && m.pairs->stats.count > 0) {
      const Histogram merged = merge_bins(m.pairs->histogram, 8);
      model["pairs"] = pairs_json(*m.pairs);
      model["pairs"]["histogram"] = {
          {"lower_mm", merged.lower}, {"upper_mm", merged.upper}, {"counts", merged.counts}};
    }
    out["models"].push_back(model);
  }
  out["distance_to_calibration_mm"] = data.distance_to_calibration_mm;
  out["rows"] = rows_json(data);
  out["parameters"] = nlohmann::json::array();
  for (const ReportParameter& p : data.parameters)
    out["parameters"].push_back({{"name", p.name},
                                 {"unit", p.unit},
                                 {"status", p.status},
                                 {"reason", p.reason},
                                 {"nominal", p.nominal},
                                 {"value", p.value},
                                 {"std_dev", p.std_dev}});
  out["groups"] = nlohmann::json::array();
  for (const GroupSignificance& g : data.groups)
    out["groups"].push_back({{"name", g.group},
                             {"enabled", g.enabled},
                             {"identified", g.identified},
                             {"wald", g.wald},
                             {"p_value", g.p_value},
                             {"significant", g.significant}});
  out["diagnostics"] = data.diagnostics;
  out["notes"] = data.notes;
  out["provenance"] = provenance_json(data.provenance);
  out["iso9283"] = data.iso9283 ? iso9283_json(*data.iso9283) : nlohmann::json(nullptr);
  out["ballbar"] = nlohmann::json::array();
  for (const auto& [label, b] : data.ballbar) {
    nlohmann::json entry = error_statistics_json(b.absolute_mm, "mm");
    entry.update({{"label", label},
                  {"signed_mean_mm", b.signed_mean_mm},
                  {"positive_share", b.positive_share},
                  {"centre_mm", {b.centre_mm.x(), b.centre_mm.y(), b.centre_mm.z()}},
                  {"centre", b.centre_fitted ? "identified" : "given"},
                  {"classes", ballbar_classes_json(b.classes)}});
    out["ballbar"].push_back(entry);
  }
  if (!data.ballbar.empty())
    out["ballbar_range"] = {
        {"nominal_length_mm", data.ballbar_range.nominal_length_mm},
        {"range_mm", data.ballbar_range.range_mm},
        {"length", data.ballbar_range.length_given ? "given" : "median of the readings"}};
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
  if (!notes.empty()) notes = "<section><h2>Notes</h2>\n" + notes + "</section>\n";
  // The data and the library go in last so that their text is never searched for markers.
  replace_all(page, "@TITLE@", title);
  replace_all(page, "@SUBTITLE@", subtitle);
  replace_all(page, "@PROVENANCE@", provenance_html(report["provenance"]));
  replace_all(page, "@SUMMARY@", summary_rows_html(report["models"]));
  replace_all(page, "@ORIENTATION@", orientation_html(report["models"]));
  replace_all(page, "@CLASSES@", classes_html(report["models"]));
  replace_all(page, "@PAIRS@", pairs_html(report["models"]));
  replace_all(page, "@ISO9283@", iso9283_html(report["iso9283"]));
  replace_all(page, "@BALLBAR@",
              report["ballbar"].empty() ? std::string()
                                        : ballbar_html(report["ballbar"], report["ballbar_range"]));
  replace_all(page, "@CLASS_PAIRS@", class_pairs_html(report["models"]));
  replace_all(page, "@RESIDUALS@", residuals_html(report));
  replace_all(page, "@TARGETS@", per_target_html(report["models"]));
  replace_all(page, "@PARAMETERS@", parameters_html(report["parameters"]));
  replace_all(page, "@GROUPS@", groups_html(report["groups"]));
  replace_all(page, "@DIAGNOSTICS@", diagnostics);
  replace_all(page, "@NOTES@", notes);
  const size_t data_at = page.find("@DATA@");
  page.replace(data_at, 6,
               script_safe(report.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)));
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
