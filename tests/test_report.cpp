// The calibration report: its JSON figures against hand-computed ones, the page's embedding,
// and the page rendered by a real browser (headless Chromium) without a script error.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/report/report.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

namespace fs = std::filesystem;

ReportData small_report() {
  ReportData data;
  data.title = "unit test </script> report";
  data.robot = "ABB IRB 120";
  data.models = {{"before", {1.0, 2.0, 3.0, 4.0}, {"1", "2", "1", "2"}},
                 {"after", {0.1, 0.2, 0.3, 0.6}, {"1", "2", "1", "2"}}};
  data.distance_to_calibration_mm = {10, 20, 30, 40};
  data.parameters = {{"link3.a", "mm", "identified", "", 270.0, 270.236, 0.004}};
  data.diagnostics = yaml_to_json("iterations: 4\nrms_mm: 0.021\nmessage: converged\n");
  return data;
}

TEST(ReportJson, SummariesAreTheHandComputedOnes) {
  const nlohmann::json report = report_json(small_report());
  const auto& before = report["models"][0]["summary"];
  EXPECT_EQ(before["count"], 4);
  EXPECT_DOUBLE_EQ(before["mean_mm"].get<double>(), 2.5);
  const double std = std::sqrt((2.25 + 0.25 + 0.25 + 2.25) / 4);  // population std, as published
  EXPECT_NEAR(before["std_mm"].get<double>(), std, 1e-12);
  EXPECT_NEAR(before["mean_plus_3std_mm"].get<double>(), 2.5 + 3 * std, 1e-12);
  EXPECT_DOUBLE_EQ(before["max_mm"].get<double>(), 4.0);
  // Per target: target "2" has rows 2 and 4 of "after": 0.2 and 0.6.
  const auto& target2 = report["models"][1]["per_target"][1];
  EXPECT_EQ(target2["target"], "2");
  EXPECT_NEAR(target2["summary"]["mean_mm"].get<double>(), 0.4, 1e-12);
  EXPECT_NEAR(target2["summary"]["max_mm"].get<double>(), 0.6, 1e-12);
  // Histograms hold every row, from 0 to the largest error.
  for (const auto& model : report["models"]) {
    uint64_t total = 0;
    for (const auto& c : model["histogram"]["counts"]) total += c.get<uint64_t>();
    EXPECT_EQ(total, 4u);
    EXPECT_GE(model["histogram"]["upper_mm"].get<double>(),
              model["summary"]["max_mm"].get<double>());
  }
  EXPECT_EQ(report["diagnostics"]["iterations"], 4.0);
  EXPECT_EQ(report["diagnostics"]["message"], "converged");
  EXPECT_EQ(report["parameters"][0]["std_dev"], 0.004);
}

TEST(ReportParameters, StandardDeviationsComeFromTheCovariance) {
  CalibratedRobot robot = CalibratedRobot::nominal(test::load_reference_truth().model, Tool{});
  robot.status[link_param(3, 1)] = ParameterStatus::Identified;
  robot.status[link_param(3, 2)] = ParameterStatus::Identified;
  robot.status[link_param(3, 3)] = ParameterStatus::Dropped;
  robot.reason[link_param(3, 3)] = "depends on link2.d";
  robot.covariance = Eigen::MatrixXd::Zero(kParameterCount, kParameterCount);
  robot.covariance(link_param(3, 1), link_param(3, 1)) = 0.0025;  // mm²: σ = 0.05 mm
  robot.covariance(link_param(3, 2), link_param(3, 2)) = 1e-8;    // rad²: σ = 1e-4 rad
  const auto rows = report_parameters(robot);
  ASSERT_EQ(rows.size(), 3u);  // fixed parameters are left out
  EXPECT_EQ(rows[0].name, "link3.a");
  EXPECT_NEAR(rows[0].std_dev, 0.05, 1e-15);
  EXPECT_EQ(rows[1].unit, "deg");
  EXPECT_NEAR(rows[1].std_dev, 1e-4 * 180 / std::numbers::pi, 1e-15);
  EXPECT_EQ(rows[2].status, "dropped");
  EXPECT_EQ(rows[2].reason, "depends on link2.d");
}

TEST(ReportDistance, NearestCalibrationPoint) {
  MeasurementSet calibration, validation;
  calibration.points = {{"c1", 0, {}, {0, 0, 0}, 0}, {"c2", 0, {}, {100, 0, 0}, 0}};
  validation.points = {{"v1", 0, {}, {30, 40, 0}, 0}, {"v2", 0, {}, {100, 0, 20}, 0}};
  const auto d = distance_to_calibration({validation}, calibration);
  ASSERT_EQ(d.size(), 2u);
  EXPECT_DOUBLE_EQ(d[0], 50.0);
  EXPECT_DOUBLE_EQ(d[1], 20.0);
}

TEST(ReportHtml, SelfContainedAndSafelyEmbedded) {
  const std::string page = report_html(report_json(small_report()), "/*CHARTJS*/");
  EXPECT_NE(page.find("/*CHARTJS*/"), std::string::npos);
  EXPECT_EQ(page.find("<script src="), std::string::npos);  // nothing loaded from outside
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  // The title's "</script>" is escaped in the HTML and in the embedded JSON.
  EXPECT_NE(page.find("unit test &lt;/script&gt; report"), std::string::npos);
  EXPECT_NE(page.find("unit test <\\/script> report"), std::string::npos);
  EXPECT_NE(page.find("id=\"render-status\" data-status=\"pending\""), std::string::npos);
}

TEST(ReportHtml, MissingChartJsIsAClearError) {
  const char* previous = std::getenv("ROBCAL_CHARTJS");
  const std::string saved = previous ? previous : "";
  setenv("ROBCAL_CHARTJS", "/nonexistent/chart.min.js", 1);
  try {
    load_chartjs();
    ADD_FAILURE() << "no error for a missing Chart.js";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("libjs-chart.js"), std::string::npos) << e.what();
  }
  if (previous)
    setenv("ROBCAL_CHARTJS", saved.c_str(), 1);
  else
    unsetenv("ROBCAL_CHARTJS");
}

/// Path of a Chromium binary, or empty.
std::string find_chromium() {
  for (const char* candidate : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(candidate)) return candidate;
  return "";
}

TEST(ReportBrowser, RendersInHeadlessChromiumWithoutScriptErrors) {
  const std::string chromium = find_chromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (Debian package chromium; `make browser-deps`)";
  std::string chartjs;
  try {
    chartjs = load_chartjs();
  } catch (const InputError& e) {
    GTEST_SKIP() << e.what();
  }
  // A report the size of a real one: 1000 rows, errors of a few mm before and 0.05 mm after.
  ReportData data = small_report();
  std::mt19937_64 rng(1);
  std::gamma_distribution<double> before(2.0, 1.5), after(2.0, 0.025);
  std::uniform_real_distribution<double> distance(0, 300);
  data.models = {{"nominal", {}, {}}, {"full", {}, {}}};
  for (int i = 0; i < 1000; ++i) {
    data.models[0].errors_mm.push_back(before(rng));
    data.models[1].errors_mm.push_back(after(rng));
    data.models[0].target_of_row.push_back(std::to_string(1 + i % 3));
    data.models[1].target_of_row.push_back(std::to_string(1 + i % 3));
    data.distance_to_calibration_mm.push_back(distance(rng));
  }
  const fs::path dir = fs::path(::testing::TempDir()) / "report_browser";
  fs::remove_all(dir);
  fs::create_directories(dir / "profile");
  const fs::path page = dir / "report.html";
  write_file_atomically(page, report_html(report_json(data), chartjs));
  const std::string flags =
      "--headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync "
      "--user-data-dir=" +
      (dir / "profile").string();
  const std::string command = "timeout 120 " + chromium + " " + flags + " --dump-dom file://" +
                              page.string() + " > " + (dir / "dom.html").string() + " 2> " +
                              (dir / "stderr.txt").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text_file(dir / "stderr.txt");
  const std::string dom = read_text_file(dir / "dom.html");
  EXPECT_NE(dom.find("data-status=\"rendered\""), std::string::npos) << dom.substr(
      dom.find("render-status") == std::string::npos ? 0 : dom.find("render-status"), 300);
  EXPECT_NE(dom.find("rendered 3 charts"), std::string::npos);  // two histograms + the scatter
  EXPECT_NE(dom.find("id=\"histogram-1\""), std::string::npos);
}

}  // namespace
}  // namespace robcal
