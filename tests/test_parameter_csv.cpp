// The parameter table CSV (identify/parameter_csv.hpp): every value and σ read back from the
// text equals the model's (external units), rows for link 1, the layout and enabled groups only.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "robcal/identify/parameter_csv.hpp"
#include "robcal/io/robot_file.hpp"
#include "test_support.hpp"

namespace robcal {
namespace {

TEST(ParameterCsv, ValuesAndSigmasRoundTrip) {
  CalibratedRobot robot = CalibratedRobot::nominal(load_robot("abb-irb120"), Tool{});
  std::mt19937_64 rng = test::seeded_rng(19);
  std::normal_distribution<double> n(0, 1);
  for (int k = 0; k < kPeriodicOffset; ++k) robot.params[k] += 1e-3 * n(rng);
  robot.params[periodic_param(6, 1, true)] = 2e-5;  // enables joint6.periodic only
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(kParameterCount, kParameterCount);
  for (int i = 0; i < kParameterCount; ++i)
    for (int j = 0; j < kParameterCount; ++j) A(i, j) = 1e-4 * n(rng);
  robot.covariance = A * A.transpose();
  for (int k = kLinkParamOffset; k < kComplianceOffset; ++k)
    robot.status[static_cast<size_t>(k)] = ParameterStatus::Identified;

  std::istringstream in(parameter_table_csv(robot));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "name,unit,nominal,value,std,status");
  const auto& table = parameter_table();
  const ParameterVector nominal = robot.model.nominal();
  int rows = 0, layout_rows = 0;
  while (std::getline(in, line)) {
    std::vector<std::string> cell;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cell.push_back(c);
    ASSERT_EQ(cell.size(), 6u) << line;
    ++rows;
    if (cell[0] == "link1.d") {
      EXPECT_EQ(std::stod(cell[3]), robot.model.mdh[0].d);
    }
    const int i = parameter_index(cell[0]);
    if (i < 0) continue;
    ++layout_rows;
    const auto s = static_cast<size_t>(i);
    const double f = table[s].to_external();
    EXPECT_EQ(cell[1], table[s].unit);
    EXPECT_EQ(std::stod(cell[2]), nominal[i] * f) << cell[0];
    EXPECT_EQ(std::stod(cell[3]), robot.params[i] * f) << cell[0];
    EXPECT_EQ(std::stod(cell[4]), std::sqrt(robot.covariance(i, i)) * f) << cell[0];
    EXPECT_EQ(cell[5], status_name(robot.status[s])) << cell[0];
  }
  // Link 1's four rows, the 37 parameters outside the opt-in groups and joint 6's periodic group.
  EXPECT_EQ(layout_rows, kPeriodicOffset + kPeriodicPerJoint);
  EXPECT_EQ(rows, 4 + layout_rows);
}

}  // namespace
}  // namespace robcal
