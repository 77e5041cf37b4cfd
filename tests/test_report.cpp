// The calibration report: its JSON figures against hand-computed ones, the page's embedding,
// and the page rendered by a real browser (headless Chromium) without a script error.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>

#include "refusal.hpp"
#include "robcal/core/error.hpp"
#include "robcal/io/atomic_file.hpp"
#include "robcal/io/measurement_file.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/kinematics/inverse_kinematics.hpp"
#include "robcal/report/provenance.hpp"
#include "robcal/report/report.hpp"
#include "robcal/report/report_workflow.hpp"
#include "robcal/validate/base_fit.hpp"
#include "robcal/validate/error_statistics.hpp"
#include "robcal/validate/validation.hpp"
#include "test_support.hpp"
#include "test_validate_support.hpp"

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

/// Headless Chromium offline, with its own profile and no header or footer on printed pages.
std::string chromium_flags(const fs::path& profile) {
  return "--headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
         "--disable-background-networking --disable-component-update --disable-sync "
         "--no-pdf-header-footer --user-data-dir=" +
         profile.string();
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
  const std::string flags = chromium_flags(dir / "profile");
  const std::string command = "timeout 120 " + chromium + " " + flags + " --dump-dom file://" +
                              page.string() + " > " + (dir / "dom.html").string() + " 2> " +
                              (dir / "stderr.txt").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << read_text_file(dir / "stderr.txt");
  const std::string dom = read_text_file(dir / "dom.html");
  EXPECT_NE(dom.find("data-status=\"rendered\""), std::string::npos) << dom.substr(
      dom.find("render-status") == std::string::npos ? 0 : dom.find("render-status"), 300);
  // The cumulative distributions, two histograms and the scatter.
  EXPECT_NE(dom.find("rendered 4 charts"), std::string::npos);
  EXPECT_NE(dom.find("id=\"histogram-1\""), std::string::npos);
}

TEST(ReportProvenance, Sha256OfTheStandardVectors) {
  // FIPS 180-4 examples (and the empty message).
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256_hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  // 55, 56 and 64 bytes: the padding's one- and two-block cases.
  EXPECT_EQ(sha256_hex(std::string(55, 'a')),
            "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256_hex(std::string(64, 'a')),
            "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(ReportProvenance, CommandLineAndJson) {
  const char* argv[] = {"robcal", "report", "--title", "two words"};
  Provenance p = start_provenance(4, argv);
  EXPECT_EQ(p.command_line, "robcal report --title 'two words'");
  EXPECT_EQ(p.robcal_version, robcal_version());
  EXPECT_TRUE(std::regex_match(p.date_utc, std::regex(R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ)")))
      << p.date_utc;
  const fs::path file = fs::path(::testing::TempDir()) / "provenance.txt";
  write_file_atomically(file, "abc");
  p.files.push_back(provenance_file("model", file.string()));
  EXPECT_EQ(p.files[0].sha256, sha256_hex("abc"));
  const nlohmann::json j = provenance_json(p);
  EXPECT_TRUE(j["seed"].is_null());
  EXPECT_TRUE(j["instrument_sigma_mm"].is_null());
  EXPECT_EQ(j["files"][0]["role"], "model");
  EXPECT_REFUSED((void)provenance_file("model", "/nonexistent/file"), InputError,
                 "/nonexistent/file: cannot open for reading");
}

/// A report the way `robcal report` builds it, on the reference data set: the nominal robot
/// (rigid base fit) and the true one over the validation rows, with calibration regions, pair
/// distances, ISO 9283 figures and ballbar errors.
ReportData reference_report() {
  const CalibratedRobot after = test::reference_true_robot();
  const MeasurementSet validation =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), after.tool,
                            {MeasurementKind::Points})
          .measurements;
  const MeasurementSet calibration =
      read_measurements_csv(test::data_path("irb120-published/calibration.csv"), after.tool,
                            {MeasurementKind::Points})
          .measurements;
  const CalibratedRobot before =
      fit_base(CalibratedRobot::nominal(after.model, after.tool), validation);
  ReportData data;
  data.title = "reference report";
  data.robot = after.model.name;
  const char* argv[] = {"robcal", "report"};
  data.provenance = start_provenance(2, argv);
  data.provenance.robot = after.model.name;
  data.provenance.level = "full";
  data.provenance.instrument = "laser-tracker";
  data.provenance.instrument_sigma_mm = 0.022;
  data.provenance.seed = 1;
  data.provenance.files.push_back(
      provenance_file("validation", test::data_path("irb120-published/validation.csv")));
  const Eigen::Matrix3Xd anchors = measured_positions(calibration);
  data.models.push_back(model_errors("nominal (rigid base fit)", before, {validation}, anchors));
  data.models.push_back(model_errors("full", after, {validation}, anchors));
  data.distance_to_calibration_mm = distance_to_calibration({validation}, calibration);
  data.parameters = report_parameters(after);
  data.groups = group_significance(after);
  data.diagnostics = yaml_to_json("iterations: 4\nrms_mm: 0.021\n");
  // ISO 9283: 4 cycles of 5 poses, 0.05 mm off in x and ±0.01 mm in y.
  Iso9283AnalysisRequest iso;
  iso.min_cycles = 3;
  for (int k = 0; k < 5; ++k)
    iso.commanded.push_back({Eigen::Matrix3d::Identity(), Eigen::Vector3d(400 + 10 * k, 0, 500)});
  for (int cycle = 1; cycle <= 4; ++cycle)
    for (int k = 1; k <= 5; ++k)
      iso.samples.push_back({k, cycle, 0,
                             iso.commanded[static_cast<size_t>(k - 1)].p +
                                 Eigen::Vector3d(0.05, cycle % 2 ? 0.01 : -0.01, 0),
                             std::nullopt, 0});
  data.iso9283 = iso9283_analyse(iso);
  // Ballbar: lengths of the true robot around a centre, 0.01 mm longer.
  MeasurementSet bar;
  bar.kind = MeasurementKind::Distances;
  const Eigen::Vector3d centre(0, 1000, 300);
  for (size_t r = 0; r < 40; ++r) {
    const PointMeasurement& m = validation.points[r];
    const Eigen::Vector3d p = flange_pose(after.model, after.tool.payload, after.params, m.joints) *
                              after.tool.targets[static_cast<size_t>(m.target)].position_mm;
    bar.distances.push_back({m.config, m.target, m.joints, (p - centre).norm() + 0.01, 0});
  }
  // The rows are spread over the arm's reach, not on one bar's sphere: a wide range.
  data.ballbar_range = check_ballbar_readings(bar, std::nullopt, 2000.0);
  data.ballbar.emplace_back("full", ballbar_errors(after, bar, centre));
  return data;
}

TEST(ReportJson, ClassesPairsIsoBallbarAndProvenance) {
  const nlohmann::json report = report_json(reference_report());
  const auto& after = report["models"][1];
  ASSERT_EQ(after["classes"].size(), 5u);
  EXPECT_EQ(after["classes"][0]["table"], "front/back");
  // The validation set has no back rows: "no data", not a number.
  EXPECT_EQ(after["classes"][0]["rows"][1]["position_mm"]["status"], "no data");
  EXPECT_EQ(after["pairs"]["count"], 1000u * 999u / 2u);
  uint64_t total = 0;
  for (const auto& c : after["pairs"]["histogram"]["counts"]) total += c.get<uint64_t>();
  EXPECT_EQ(total, 1000u * 999u / 2u);
  // Round histogram bins: the width is 1, 2, 2.5 or 5 × 10^k.
  for (const auto& m : report["models"]) {
    const auto& h = m["histogram"];
    const double width = (h["upper_mm"].get<double>() - h["lower_mm"].get<double>()) /
                         static_cast<double>(h["counts"].size());
    const double mantissa = width / std::pow(10.0, std::floor(std::log10(width) + 1e-12));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 ||
                std::abs(mantissa - 2.5) < 1e-9 || std::abs(mantissa - 5) < 1e-9)
        << width;
    EXPECT_GT(h["upper_mm"].get<double>(), m["summary"]["max_mm"].get<double>());
  }
  EXPECT_NEAR(report["iso9283"]["poses"][0]["AP_mm"].get<double>(), 0.05, 1e-9);
  EXPECT_NEAR(report["ballbar"][0]["mean_mm"].get<double>(), 0.01, 1e-9);
  EXPECT_EQ(report["ballbar"][0]["positive_share"], 1.0);
  EXPECT_EQ(report["provenance"]["instrument_sigma_mm"], 0.022);
  EXPECT_EQ(report["provenance"]["files"][0]["sha256"].get<std::string>().size(), 64u);
}

// The page's tables read the statistics' unit-bearing keys (error_statistics_json): every cell of
// the orientation and by-class tables shows the number, "no data" only for an empty class.
TEST(ReportHtml, TablesShowTheStatisticsNumbers) {
  ReportData data = reference_report();
  for (ModelErrors& m : data.models)
    for (size_t r = 0; r < m.errors_mm.size(); ++r)
      m.orientation_deg.push_back(0.001 * static_cast<double>(r % 7 + 1));
  const nlohmann::json report = report_json(data);
  const std::string html = report_html(report, "");
  const auto table = [&](const std::string& opening) {
    const size_t at = html.find(opening);
    EXPECT_NE(at, std::string::npos) << opening;
    return at == std::string::npos ? "" : html.substr(at, html.find("</table>", at) - at);
  };
  const std::string orientation = table("<table id=\"orientation\">");
  EXPECT_EQ(orientation.find("nodata"), std::string::npos);
  const ErrorStatistics o = error_statistics(data.models[1].orientation_deg);
  EXPECT_NE(orientation.find(fmt::format("<td>{:.4f}</td><td>{:.4f}</td><td>{:.4f}</td>", o.mean,
                                         o.std, o.mean_plus_3std())),
            std::string::npos);
  // The front/back class table: "front" has every row, "back" none.
  const std::string classes = table("<table class=\"classes\">");
  const ErrorStatistics front = error_statistics(data.models[1].errors_mm);
  EXPECT_NE(classes.find(fmt::format("<td>{}</td><td>{:.4f}</td><td>{:.4f}</td>", front.count,
                                     front.mean, front.max)),
            std::string::npos)
      << classes;
}

TEST(ReportJson, ResidualsPerConfigurationAndPairsByClass) {
  const ReportData data = reference_report();
  const nlohmann::json report = report_json(data);
  const CalibratedRobot truth = test::reference_true_robot();
  const MeasurementSet validation =
      read_measurements_csv(test::data_path("irb120-published/validation.csv"), truth.tool,
                            {MeasurementKind::Points})
          .measurements;
  // Every row: its name, target, class and each model's error, in file order.
  ASSERT_EQ(report["rows"].size(), validation.size());
  size_t front = 0;
  for (size_t r = 0; r < validation.size(); ++r) {
    const auto& row = report["rows"][r];
    const PointMeasurement& m = validation.points[r];
    EXPECT_EQ(row["config"], m.config);
    EXPECT_EQ(row["target"], std::to_string(m.target + 1));  // targets "1", "2", "3"
    const ArmConfig config = arm_config(truth.model, m.joints);
    EXPECT_EQ(row["class"], config.label());
    front += config.back ? 0 : 1;
    for (size_t k = 0; k < 2; ++k)
      EXPECT_EQ(row["errors_mm"][k].get<double>(), data.models[k].errors_mm[r]);
    EXPECT_EQ(row["distance_to_calibration_mm"].get<double>(), data.distance_to_calibration_mm[r]);
  }
  // Pair distances by class: the pairs with both rows in the class; none for a class of fewer
  // than two rows ("no data", never a number).
  const auto& front_back = report["models"][1]["classes"][0];
  EXPECT_EQ(front_back["rows"][0]["pairs"]["count"], front * (front - 1) / 2);
  EXPECT_EQ(front_back["rows"][1]["pairs"]["status"], "no data");
  // The page shows the 20 largest errors of the last model, largest first.
  const std::string html = report_html(report, "");
  const size_t table = html.find("<table id=\"residuals\">");
  ASSERT_NE(table, std::string::npos);
  const std::string body = html.substr(table, html.find("</table>", table) - table);
  std::vector<double> sorted = data.models[1].errors_mm;
  std::sort(sorted.rbegin(), sorted.rend());
  size_t rows = 0;
  for (size_t at = body.find("<tr><td>"); at != std::string::npos;
       at = body.find("<tr><td>", at + 1))
    ++rows;
  EXPECT_EQ(rows, 20u);
  EXPECT_NE(body.find(fmt::format("<td>{:.4f}</td>", sorted[0])), std::string::npos);
  EXPECT_NE(body.find(fmt::format("<td>{:.4f}</td>", sorted[19])), std::string::npos);
  EXPECT_NE(html.find("By configuration class (pairs of rows both in the class)"),
            std::string::npos);
}

TEST(ReportWorkflow, TitleIsOneLineOfPrintableUtf8) {
  const auto refusal = [](const std::string& title) {
    ReportRequest request;
    request.title = title;
    return test::refusal_message([&] { (void)build_report(request); });
  };
  const std::string expected = ": expected one line of printable UTF-8 text";
  EXPECT_EQ(refusal(""), "--title: the title is empty" + expected);
  EXPECT_EQ(refusal("   "), "--title: the title is empty" + expected);
  EXPECT_EQ(refusal("one\ntwo"), "--title: control character 0x0A at byte 4" + expected);
  EXPECT_EQ(refusal("a\x7f"), "--title: control character 0x7F at byte 2" + expected);
  EXPECT_EQ(refusal("Report\xff"), "--title: byte 0xFF at byte 7 is not UTF-8" + expected);
  EXPECT_EQ(refusal("\xc0\xaf"),
            "--title: byte 0xC0 at byte 1 is not UTF-8" + expected);  // overlong
  EXPECT_EQ(refusal("\xed\xa0\x80"),
            "--title: byte 0xED at byte 1 is not UTF-8" + expected);  // surrogate
  EXPECT_EQ(refusal("ab\xe2\x82"),
            "--title: byte 0xE2 at byte 3 is not UTF-8" + expected);  // truncated
  EXPECT_EQ(refusal(std::string(201, 'a')),
            "--title: the title has 201 bytes, more than 200" + expected);
  // Accepted: UTF-8 beyond ASCII, and markup (escaped in the page, see ReportHtml).
  EXPECT_EQ(refusal("Kalibrierung ± 0,02 mm — Zelle 3 <b>"),
            "--measurements: expected at least one validation file");
}

TEST(ReportWorkflow, NominalRowIsFittedOnTheCalibrationData) {
  const CalibratedRobot truth = test::reference_true_robot();
  const fs::path dir = fs::path(::testing::TempDir()) / "report_nominal";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_file_atomically(dir / "model.yaml", calibrated_robot_to_yaml(truth));
  ReportRequest request;
  request.model = (dir / "model.yaml").string();
  request.measurements = {test::data_path("irb120-published/validation.csv")};
  const auto read = [&](const char* name) {
    return read_measurements_csv(test::data_path(name), truth.tool, {MeasurementKind::Points})
        .measurements;
  };
  const MeasurementSet validation = read("irb120-published/validation.csv");
  const MeasurementSet calibration = read("irb120-published/calibration.csv");
  const CalibratedRobot nominal = CalibratedRobot::nominal(truth.model, truth.tool);
  const auto rms = [](const std::vector<double>& e) {
    double sum = 0;
    for (const double v : e) sum += v * v;
    return std::sqrt(sum / static_cast<double>(e.size()));
  };
  // With --calibration: the base comes from the calibration rows, as the demo places it.
  request.calibration = test::data_path("irb120-published/calibration.csv");
  const ReportBuild with = build_report(request);
  EXPECT_EQ(with.data.models.front().label, "nominal (base fitted on the calibration data)");
  const std::vector<double> expected =
      validate_model(fit_base(nominal, calibration), validation, 1).positions.position_error_mm;
  ASSERT_EQ(with.data.models.front().errors_mm.size(), expected.size());
  for (size_t r = 0; r < expected.size(); ++r)
    EXPECT_NEAR(with.data.models.front().errors_mm[r], expected[r], 1e-9);
  // Without: only the validation rows can place it, which the label says; that fit minimises
  // the squared errors over these very rows, so it can only look better.
  request.calibration.clear();
  const ReportBuild without = build_report(request);
  EXPECT_EQ(without.data.models.front().label, "nominal (base fitted on the validation data)");
  EXPECT_LT(rms(without.data.models.front().errors_mm), rms(expected));
  // The calibrated model's row does not depend on where the nominal one was placed.
  EXPECT_EQ(without.data.models.back().errors_mm, with.data.models.back().errors_mm);
}

/// Runs `command`, failing the test with its stderr when it fails.
void run(const std::string& command, const fs::path& err) {
  ASSERT_EQ(std::system((command + " 2> " + err.string()).c_str()), 0) << read_text_file(err);
}

TEST(ReportBrowser, PrintsToPdfWithoutAHeadingAloneAtAPageFoot) {
  const std::string chromium = find_chromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (Debian package chromium; `make browser-deps`)";
  if (!fs::exists("/usr/bin/pdftotext") || !fs::exists("/usr/bin/pdfinfo"))
    GTEST_SKIP() << "pdftotext is not installed (Debian package poppler-utils)";
  std::string chartjs;
  try {
    chartjs = load_chartjs();
  } catch (const InputError& e) {
    GTEST_SKIP() << e.what();
  }
  const fs::path dir = fs::path(::testing::TempDir()) / "report_pdf";
  fs::remove_all(dir);
  fs::create_directories(dir / "profile");
  const fs::path page = dir / "report.html", pdf = dir / "report.pdf", err = dir / "stderr.txt";
  ReportData data = reference_report();
  // Orientation errors as a poses file gives them, for the orientation table.
  for (size_t k = 0; k < data.models.size(); ++k)
    for (size_t r = 0; r < data.models[k].errors_mm.size(); ++r)
      data.models[k].orientation_deg.push_back(0.001 *
                                               static_cast<double>((r % 7 + 1) * (k ? 1 : 20)));
  const std::string html = report_html(report_json(data), chartjs);
  write_file_atomically(page, html);
  const std::string flags = chromium_flags(dir / "profile");
  run("timeout 120 " + chromium + " " + flags + " --dump-dom file://" + page.string() + " > " +
          (dir / "dom.html").string(),
      err);
  const std::string dom = read_text_file(dir / "dom.html");
  // Every chart drawn: CDF, two histograms, the scatter and two pair histograms.
  EXPECT_NE(dom.find("data-status=\"rendered\">rendered 6 charts"), std::string::npos)
      << dom.substr(dom.find("render-status") == std::string::npos ? 0 : dom.find("render-status"),
                    300);
  run("timeout 120 " + chromium + " " + flags + " --print-to-pdf=" + pdf.string() + " file://" +
          page.string(),
      err);
  run("pdfinfo " + pdf.string() + " > " + (dir / "info.txt").string(), err);
  const std::string info = read_text_file(dir / "info.txt");
  std::smatch pages_match;
  ASSERT_TRUE(std::regex_search(info, pages_match, std::regex(R"(Pages:\s+(\d+))"))) << info;
  const int pages = std::stoi(pages_match[1]);
  EXPECT_GE(pages, 2);

  // The headings of the page, as the PDF's text shows them.
  std::vector<std::string> headings;
  const std::regex heading(R"(<h[123][^>]*>([^<]*)</h[123]>)");
  for (auto it = std::sregex_iterator(html.begin(), html.end(), heading);
       it != std::sregex_iterator(); ++it) {
    std::string text = (*it)[1];
    for (const auto& [from, to] :
         {std::pair<std::string, std::string>{"&amp;", "&"}, {"&lt;", "<"}, {"&gt;", ">"}})
      for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at))
        text.replace(at, from.size(), to);
    headings.push_back(text);
  }
  for (const char* section :
       {"Provenance", "Orientation error (deg)", "Before and after on shared axes",
        "Errors by configuration class (mm)", "Residuals per configuration",
        "Distance errors over every pair of validation rows (mm)",
        "By configuration class (pairs of rows both in the class)", "ISO 9283 pose characteristics",
        "Ballbar length errors (mm)", "Length error by configuration class (mm)",
        "Parameters (± one standard deviation)",
        "Parameter groups (Wald test, significant when p < 0.001)"})
    EXPECT_NE(std::find(headings.begin(), headings.end(), section), headings.end()) << section;
  const auto trim = [](std::string line) {
    line.erase(0, line.find_first_not_of(" \t\f"));
    line.erase(line.find_last_not_of(" \t\f\r") + 1);
    return line;
  };
  std::string all_text;
  for (int p = 1; p <= pages; ++p) {
    const fs::path text = dir / ("page" + std::to_string(p) + ".txt");
    run(fmt::format("pdftotext -f {} -l {} {} {}", p, p, pdf.string(), text.string()), err);
    std::vector<std::string> lines;
    std::istringstream in(read_text_file(text));
    for (std::string line; std::getline(in, line);)
      if (!trim(line).empty()) lines.push_back(trim(line));
    const auto is_heading = [&](const std::string& line) {
      return std::find(headings.begin(), headings.end(), line) != headings.end();
    };
    SCOPED_TRACE("page " + std::to_string(p));
    ASSERT_FALSE(lines.empty());
    EXPECT_FALSE(std::all_of(lines.begin(), lines.end(), is_heading)) << "only headings";
    EXPECT_FALSE(is_heading(lines.back())) << "ends with the heading '" << lines.back() << "'";
    all_text += read_text_file(text);
  }
  for (const char* section :
       {"Provenance", "ISO 9283 pose characteristics", "no data", "SHA-256", "laser-tracker"})
    EXPECT_NE(all_text.find(section), std::string::npos) << section;
  EXPECT_FALSE(std::regex_search(all_text, std::regex(R"(\bnan\b)", std::regex::icase)));
}

}  // namespace
}  // namespace robcal
