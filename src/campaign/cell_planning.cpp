#include "robcal/campaign/cell_planning.hpp"

namespace robcal::campaign {

Eigen::Matrix<double, 6, 1> base_parameters(const Cell& cell) {
  return Eigen::Map<const Eigen::Matrix<double, 6, 1>>(cell.robot_base.data());
}

VirtualInstrument virtual_instrument(const Cell& cell, const Tool& tool) {
  const CellInstrument& in = cell.instrument;
  VirtualInstrument out;
  out.kind = in.kind;
  std::vector<Eigen::Vector3d> axes;
  for (size_t t = 0; t < tool.targets.size(); ++t) {
    Eigen::Vector3d axis = smr_axis_flange(LaserTracker{}, tool, static_cast<int>(t));
    for (const auto& [name, given] : in.target_axes_flange)
      if (name == tool.targets[t].name) axis = given;
    axes.push_back(axis);
  }
  if (in.kind == InstrumentKind::LaserTracker) {
    out.tracker.position_mm = in.position_mm;
    out.tracker.min_range_mm = in.min_range_mm;
    out.tracker.max_range_mm = in.max_range_mm;
    out.tracker.cone_half_angle_deg = in.cone_half_angle_deg;
    if (in.sigma_mm > 0) out.tracker.sigma_mm.setConstant(in.sigma_mm);
    out.tracker.smr_axes_flange = axes;
  } else {
    out.cmm.position_mm = in.position_mm;
    out.cmm.min_range_mm = in.min_range_mm;
    out.cmm.max_range_mm = in.max_range_mm;
    out.cmm.facing_limit_deg = in.facing_limit_deg;
    if (in.sigma_mm > 0) out.cmm.sigma_mm = in.sigma_mm;
    if (!in.target_axes_flange.empty()) out.cmm.face_normals_flange = axes;
  }
  return out;
}

CandidateSet candidate_set(const CellCandidates& c) {
  CandidateSet out;
  for (size_t i = 0; i < c.joints.size(); ++i)
    out.candidates.push_back({c.joints[i], c.targets[i]});
  const RejectionCounts& r = c.rejected;
  out.below_floor = r.of(Rejection::BelowFloor) + r.of(Rejection::Collision);
  out.not_visible = r.of(Rejection::OutOfRange) + r.of(Rejection::NotFacing) +
                    r.of(Rejection::OutsideView) + r.of(Rejection::Occluded) +
                    r.of(Rejection::TooFewTargets);
  out.draws = c.draws - r.of(Rejection::JointLimits);
  return out;
}

}  // namespace robcal::campaign
