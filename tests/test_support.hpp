#pragma once
// Shared test helpers: the reference data set, a small CSV table reader, seeded RNG, and the
// finite-difference Jacobian check (STYLE practice 6).

#include <Eigen/Core>
#include <fstream>
#include <functional>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "robcal/core/units.hpp"
#include "robcal/io/robot_file.hpp"
#include "robcal/model/robot_model.hpp"

namespace robcal::test {

/// A file of the test data folder (tests/data/), by its path inside it.
std::string data_path(const std::string& relative);

/// A numeric CSV table with a header row; '#' lines are skipped.
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  [[nodiscard]] int column(const std::string& name) const {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    return -1;
  }
  [[nodiscard]] double at(size_t row, const std::string& name) const {
    return rows.at(row).at(static_cast<size_t>(column(name)));
  }
};

inline CsvTable read_csv(const std::string& path) {
  CsvTable table;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    if (table.header.empty()) {
      while (std::getline(ss, cell, ',')) table.header.push_back(cell);
      continue;
    }
    std::vector<double> row;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    table.rows.push_back(row);
  }
  return table;
}

/// The true robot of the reference set (tests/data/irb120-published/truth.yaml) as a
/// parameter vector of the IRB 120 model, with its payload.
struct ReferenceTruth {
  RobotModel model;
  ParameterVector params;
  PointMass payload;
};

inline ReferenceTruth load_reference_truth() {
  ReferenceTruth truth;
  truth.model = load_robot("abb-irb120");
  const auto root = yaml::load_file(data_path("irb120-published/truth.yaml"));
  truth.params = truth.model.nominal();
  const auto base = root.at("base");
  truth.params[0] = base.at("x_mm").as_double();
  truth.params[1] = base.at("y_mm").as_double();
  truth.params[2] = base.at("z_mm").as_double();
  truth.params[3] = deg2rad(base.at("alpha_deg").as_double());
  truth.params[4] = deg2rad(base.at("beta_deg").as_double());
  truth.params[5] = deg2rad(base.at("gamma_deg").as_double());
  for (int link = 2; link <= 6; ++link) {
    const auto row = root.at("links").at(std::to_string(link)).as_doubles(5);
    truth.params[link_param(link, 0)] = deg2rad(row[0]);
    truth.params[link_param(link, 1)] = row[1];
    truth.params[link_param(link, 2)] = deg2rad(row[2]);
    truth.params[link_param(link, 3)] = row[3];
    truth.params[compliance_param(link)] = row[4];
  }
  const auto payload = root.at("masses").at("payload");
  truth.payload.mass_kg = payload.at(0).as_double();
  truth.payload.cog_mm = payload.at(1).as_vector3();
  return truth;
}

/// Central-difference Jacobian of f: R^n -> R^m at x.
inline Eigen::MatrixXd numerical_jacobian(
    const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f, const Eigen::VectorXd& x,
    double step = 1e-6) {
  const Eigen::VectorXd f0 = f(x);
  Eigen::MatrixXd J(f0.size(), x.size());
  for (int j = 0; j < x.size(); ++j) {
    Eigen::VectorXd xp = x, xm = x;
    xp[j] += step;
    xm[j] -= step;
    J.col(j) = (f(xp) - f(xm)) / (2 * step);
  }
  return J;
}

/// Seeded generator; tests print the seed on failure through SCOPED_TRACE.
inline std::mt19937_64 seeded_rng(uint64_t seed) {
  return std::mt19937_64(seed);
}

}  // namespace robcal::test
