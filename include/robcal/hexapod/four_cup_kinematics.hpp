#pragma once
/// \file
/// Direct kinematics of a ballbar hexapod with a fourth cup on either fixture (issue 20,
/// docs/method/07-hexapod.md §7 extended): more distances than unknowns, so the cup positions are
/// the least-squares fit of every measured distance (fixture sides and legs), by Gauss–Newton
/// started from the closed-form 3-3 cascade on the cups 1..3. The same Jacobian gives the GUM
/// sensitivity of every tool-cup coordinate to every distance (ISO/IEC Guide 98-3; at the
/// least-squares solution ∂x/∂d = (JᵀJ)⁻¹Jᵀ), checked against Monte Carlo.
///
/// Frame: the base fixture frame of cups 1..3 (b1 at the origin, b2 on +x, b3 in the xy plane
/// with y > 0; fixture.hpp). A fourth cup need not be in its fixture's plane.

#include <Eigen/Core>

#include <array>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "robcal/hexapod/direct_kinematics.hpp"
#include "robcal/hexapod/uncertainty.hpp"

namespace robcal::hexapod {

/// One measured leg between physical cups (0-based: base cup B(base+1), tool cup T(tool+1)).
struct MeasuredLeg {
  int base = 0;
  int tool = 0;
  double length_mm = 0;
};

struct FourCupDkpRequest {
  FixtureDistances base;
  FixtureDistances tool;
  std::vector<MeasuredLeg> legs;  ///< must include a 1^12 2^123 3^1 design on cups 1..3
};

/// One least-squares solution, started from one assembly mode of the cascade.
struct FourCupSolution {
  int mode = 0;  ///< assembly mode 1..4 of the starting cascade (design of `design`)
  std::vector<Eigen::Vector3d> base_cups;  ///< physical B1..B3(4), base fixture frame, mm
  std::vector<Eigen::Vector3d> tool_cups;  ///< physical T1..T3(4), base fixture frame, mm
  double rms_residual_mm = 0;              ///< of all distances at the solution
  double max_residual_mm = 0;
  int iterations = 0;
  /// ∂(tool-cup coordinate)/∂(distance): rows T1x, T1y, T1z, T2x, …; columns in the order of
  /// FourCupDkpResult::distance_names.
  Eigen::MatrixXd sensitivity;
  /// Standard uncertainty of each tool cup for independent distances of equal σ, in multiples of σ.
  std::vector<CupUncertainty> uncertainty;
};

enum class FourCupDkpStatus { Ok, InvalidInput, NotDetermined, NoRealSolution };

/// The part of a request a problem lies in (what a caller names: the CLI's --base-mm, --tool-mm
/// or --legs).
enum class FourCupInput { BaseFixture, ToolFixture, Legs };

struct FourCupDkpResult {
  FourCupDkpStatus status = FourCupDkpStatus::Ok;
  std::string message;  ///< what is wrong when status != Ok
  FourCupInput culprit =
      FourCupInput::Legs;                   ///< where it is wrong (fixture problems: that fixture)
  std::vector<std::string> distance_names;  ///< "b12", …, "b34", "t12", …, "rho11", …
  LegDesign design;                         ///< the 3-3 design the cascade started from
  /// Distinct converged solutions, smallest residual first. With redundant legs the true
  /// assembly mode is usually the only one with a residual at the gauge's σ.
  std::vector<FourCupSolution> solutions;
};

/// Solves the over-determined direct kinematics. Ill-posed input (a fixture problem, a leg not
/// positive or naming a cup the fixture lacks, a fourth cup without a leg, no 3-3 design among
/// the legs, a rank-deficient fit) is reported in the status and message, never thrown.
FourCupDkpResult solve_four_cup_dkp(const FourCupDkpRequest& request);

/// The distances of a configuration (the inverse problem): the fixtures' sides and the lengths
/// of `legs` between `base_cups` and `tool_cups` (one frame). For round trips and simulation.
FourCupDkpRequest four_cup_distances(const std::vector<Eigen::Vector3d>& base_cups,
                                     const std::vector<Eigen::Vector3d>& tool_cups,
                                     const std::vector<PhysicalLeg>& legs);

/// Monte Carlo check of a solution's GUM uncertainty: `samples` draws of independent
/// N(0, sigma_mm) errors on every distance of `request`, each solved and matched to the
/// solution nearest `reference`; returns each tool cup's sample standard deviations / sigma_mm.
/// Throws InputError when sigma_mm is not positive, samples < 2 or fewer than 2 draws converge.
std::vector<CupUncertainty> four_cup_uncertainty_monte_carlo(const FourCupDkpRequest& request,
                                                             const FourCupSolution& reference,
                                                             double sigma_mm, int samples,
                                                             std::mt19937_64& rng);

/// The worst standard uncertainty of a tool cup T1..T3 (multiples of one distance's σ,
/// docs/method/07-hexapod.md §4) over `poses` of `geometry`, every distance at its planned value:
/// solved from the fixture sides and the six design legs (`design_legs`), and from every leg of
/// the pose with a fourth cup's distances (either fixture) when a leg reaches it (`all_legs`).
/// Throws std::logic_error when a planned pose has no solution (the poses are not of this
/// geometry).
struct WorstToolCupUncertainty {
  double design_legs = 0, all_legs = 0;
};
WorstToolCupUncertainty worst_tool_cup_uncertainty(const std::vector<HexapodPose>& poses,
                                                   const HexapodGeometry& geometry);

}  // namespace robcal::hexapod
