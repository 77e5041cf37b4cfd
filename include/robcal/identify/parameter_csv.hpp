#pragma once
/// \file
/// A calibrated model's parameter table as CSV (`robcal model export --format mdh-csv`): the
/// Modified DH table (link 1's α, a, θ, d from the model, links 2..6 identified), the base
/// placement, compliances and scales, one row each: name, unit, nominal, value, std (1σ from
/// the covariance, 0 when not identified), status. External units (mm, deg); values written
/// with the shortest text that reads back to the same double.

#include <string>

#include "robcal/identify/calibrated_robot.hpp"

namespace robcal {

/// Header "name,unit,nominal,value,std,status". Opt-in groups (periodic errors) appear only
/// when enabled, as in the model file.
std::string parameter_table_csv(const CalibratedRobot& robot);

}  // namespace robcal
