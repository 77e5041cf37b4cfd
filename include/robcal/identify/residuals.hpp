#pragma once
/// \file
/// Residuals of the identification (docs/method/04-identification.md §1) and their exact
/// derivatives with respect to the unknown vector (model parameters + extras, see unknowns.hpp),
/// built on the analytic twist Jacobian of the flange:
/// - points: r = p_model − p_measured (3, mm);
/// - poses: TCP position (3, mm) and orientation r = w·vee(½(A − Aᵀ)), A = R_model·R_measuredᵀ
///   (≈ w·rotation vector; w = `orientation_weight_mm`, mm per rad, makes an orientation error
///   count like the displacement it causes at that distance);
/// - distances: r = |p_model − centre| − (length + length_offset) (1, mm).

#include <Eigen/Core>

#include "robcal/identify/unknowns.hpp"
#include "robcal/kinematics/parameter_jacobian.hpp"
#include "robcal/measure/measurements.hpp"
#include "robcal/model/robot_model.hpp"
#include "robcal/model/tool.hpp"

namespace robcal {

/// Orientation residual weight of pose measurements: an orientation error of θ rad counts as
/// θ·100 mm, the displacement it causes across a 100 mm target cluster (how an optical CMM
/// sees it).
inline constexpr double kDefaultOrientationWeightMm = 100.0;

/// InputError (key `--orientation-weight`) unless the weight is a positive finite number.
void check_orientation_weight(double weight_mm);

/// Everything a residual needs besides the unknowns (not owned; must outlive the context).
struct ResidualContext {
  const RobotModel* model = nullptr;
  const Tool* tool = nullptr;
  const MeasurementSet* data = nullptr;
  const UnknownLayout* layout = nullptr;
  double orientation_weight_mm = kDefaultOrientationWeightMm;
};

/// Residuals of one row (data->residuals_per_row() values into `residuals`) and, when
/// `jacobian` is not null, their derivative with respect to every unknown (rows × layout size,
/// fully overwritten).
void row_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns, size_t row,
                   double* residuals, Eigen::MatrixXd* jacobian);

/// The same for the row's configuration prepared once (prepare_configuration, at parameters
/// near `unknowns`) and the parameters' trig: the identification's inner loop, which then
/// makes no trigonometric call and, once `jacobian` has its size, no allocation.
void row_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns, size_t row,
                   const ParameterTrig& trig, const PreparedConfiguration& configuration,
                   double* residuals, Eigen::MatrixXd* jacobian);

/// The same from the row's chain already evaluated at `unknowns` (FlangeRegressor): the
/// identification reuses the chain of a residual-only evaluation for the Jacobian at that point.
void row_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns, size_t row,
                   const FlangeRegressor& regressor, double* residuals, Eigen::MatrixXd* jacobian);

/// The joint values (controller, rad) of a row of any kind.
const Vector6d& row_joints(const MeasurementSet& data, size_t row);

/// Each joint's approach in a row of any kind (+1 from below, −1 from above, 0 unknown).
const Vector6d& row_approach(const MeasurementSet& data, size_t row);

/// A row's approach, its temperature rise over `model`'s reference temperature (0 when the row
/// records none) and its warm-up φ at its time (0 without one), what the opt-in groups need
/// beyond the joints.
RowConditions row_conditions(const RobotModel& model, const MeasurementSet& data, size_t row);

/// All residuals stacked row by row, and the Jacobian restricted to the `columns` unknowns
/// (in that order) when `jacobian` is not null.
void stacked_residuals(const ResidualContext& context, const Eigen::VectorXd& unknowns,
                       const std::vector<int>& columns, Eigen::VectorXd* residuals,
                       Eigen::MatrixXd* jacobian);

/// The world position of a row's target (points, distances) or TCP (poses) in the model.
Eigen::Vector3d modelled_position(const ResidualContext& context, const Eigen::VectorXd& unknowns,
                                  size_t row);

/// The TCP frame in the flange (mm) in the unknown vector's state: the tool's, with its
/// identified parts (tcp.x..z; tcp.rx..rz as φ in flange_T_tcp = start·exp([φ]×)).
Eigen::Isometry3d tcp_frame(const ResidualContext& context, const Eigen::VectorXd& unknowns);

/// Right Jacobian of SO(3): exp([φ + δ]×) ≈ exp([φ]×)·exp([J_r(φ)·δ]×).
Eigen::Matrix3d so3_right_jacobian(const Eigen::Vector3d& phi);

/// The coordinates (flange frame, mm) of tool target `target` in the unknown vector's state.
Eigen::Vector3d target_coordinates(const ResidualContext& context, const Eigen::VectorXd& unknowns,
                                   int target);

}  // namespace robcal
