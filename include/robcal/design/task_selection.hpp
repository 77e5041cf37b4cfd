#pragma once
/// \file
/// Task-aware choice of calibration configurations (docs/method/05-observability.md §5, "Selection
/// for a task region"): the I-optimal (V-optimal) criterion minimises the average predicted
/// position variance over task-region configurations,
///   Φ_I(S) = tr(M_S⁻¹ B),  M_S = ridge·I + Σ_{i∈S} A_iᵀA_i,  B = (1/T) Σ_t J_tᵀJ_t,
/// with A_i the candidates' scaled design rows and J_t the TCP position Jacobian at task
/// configuration t in the same column scaling, so that σ²·Φ_I is the mean over the task region
/// of the predicted squared TCP error. A robustness guard keeps the choice away from what makes
/// D-optimal designs fragile on real robots (their effects outside the model are largest at the
/// extreme poses D-optimality favours): at most a stated share of the chosen configurations near a
/// joint-range edge and a minimum spacing between chosen configurations.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "robcal/design/candidates.hpp"
#include "robcal/design/design_matrix.hpp"
#include "robcal/design/selection.hpp"

namespace robcal {

/// B = (1/T)·J_sᵀJ_s of the stacked task Jacobian (3T × columns, internal units, columns
/// design.parameters) with the design's column scaling applied.
Eigen::MatrixXd task_information(const DesignMatrix& design, const Eigen::MatrixXd& task_jacobian);

/// The robustness guard (numbers justified in docs/method/05-observability.md §5).
struct SelectionGuard {
  bool enabled = true;
  /// A configuration is near an edge when some joint is within this fraction of its range
  /// (the constrained joint box) from either end.
  double edge_margin = 0.05;
  /// At most this share of the chosen configurations near an edge (rounded down).
  double max_edge_share = 0.25;
  /// Any two chosen configurations differ by at least this fraction of the range in some joint.
  double min_spacing = 0.05;
  /// At least this share of the chosen configurations (rounded up) among the candidates near
  /// the task region (calibration_planning.hpp near_task_region), when there are such
  /// candidates: TCP inside the task region's TCP box grown by task_margin_mm.
  double min_task_share = 0.5;
  double task_margin_mm = 100;
  /// The constrained joint box the fractions refer to (controller values, rad).
  std::array<JointLimit, kJointCount> box{};
};

/// Whether `joints` is near an edge of the guard's box.
bool near_joint_edge(const SelectionGuard& guard, const Vector6d& joints);

/// Greatest fraction of its range by which two configurations differ in one joint.
double joint_spacing(const SelectionGuard& guard, const Vector6d& a, const Vector6d& b);

/// The most chosen configurations near an edge for `count` of them: ⌊max_edge_share·count⌋
/// (`count` when the guard is off).
int guard_edge_limit(const SelectionGuard& guard, int count);

struct TaskSelection {
  std::vector<int> chosen;  ///< candidate indices, in the order they were added
  double criterion = 0;     ///< tr(M_S⁻¹ B) of the chosen set
  int exchanges = 0;        ///< accepted remove/add exchanges after the greedy fill
  int near_edge = 0;        ///< chosen configurations near a joint-range edge
};

/// I-optimal choice of `count` candidates (joints[i] is candidate i's configuration, for the
/// guard; in_task[i] ≠ 0 when candidate i is a task-region configuration, empty: none is): greedy
/// additions from a small ridge, each the admissible candidate that lowers tr(M⁻¹B) most, then
/// exchanges (remove the chosen configuration whose removal raises it least, add the best
/// admissible candidate) while the criterion decreases. Candidate i's gain tr((I + A_iPA_iᵀ)⁻¹
/// V_iV_iᵀ), V_i = A_i P L (B = LLᵀ, P = M⁻¹), is kept current under the rank-r changes of P, so a
/// step costs O(N r² m). Deterministic. `start` (distinct candidate indices, at most `count`):
/// chosen before the greedy fill, so the search starts from that design; the exchanges may still
/// remove them. A design whose candidates pay off only in groups (a placement's world frame needs
/// two configurations before the second adds information) is not reached by one-at-a-time steps
/// from nothing; started from a design holding such groups, it is. InputError (key
/// `--count`) when fewer than `count` candidates, or when the guard leaves fewer admissible.
TaskSelection select_i_optimal(const DesignMatrix& design, const Eigen::MatrixXd& task_information,
                               int count, const std::vector<Vector6d>& joints,
                               const SelectionGuard& guard, const std::vector<char>& in_task = {},
                               const std::vector<int>& start = {});

/// tr(M_S⁻¹ B) of a subset (the same ridge as the selection); +∞ when M_S is singular.
double i_criterion(const DesignMatrix& design, const Eigen::MatrixXd& task_information,
                   const std::vector<int>& subset);

}  // namespace robcal
