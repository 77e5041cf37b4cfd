// Python bindings of the configuration design (include/robcal/design/): observability
// indices and D-optimal selection on a stacked, column-scaled Jacobian given as a matrix.

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <random>

#include "module_registry.hpp"
#include "robcal/design/observability.hpp"
#include "robcal/design/selection.hpp"

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
      "O1…O5 (docs/method/05-observability.md) of a column-scaled identification Jacobian of n "
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
});

}  // namespace
}  // namespace robcal::python
