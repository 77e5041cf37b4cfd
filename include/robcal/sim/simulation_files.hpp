#pragma once
/// \file
/// The folder a simulation writes: exactly the files a real campaign gives (measurements CSV,
/// tool YAML, instrument YAML), plus the truth kept apart under truth/ (the pipeline never
/// reads it).

#include <filesystem>
#include <string>

#include "robcal/sim/simulator.hpp"

namespace robcal {

/// The instrument's description (kind, placement, σ; ballbar centre and nominal length), YAML.
std::string instrument_to_yaml(const VirtualInstrument& instrument);

/// Paths of the files one simulation writes into a folder.
struct SimulationFiles {
  std::filesystem::path measurements;  ///< <dir>/<stem>.csv
  std::filesystem::path tool;          ///< <dir>/tool.yaml
  std::filesystem::path instrument;    ///< <dir>/instrument.yaml
  std::filesystem::path truth;         ///< <dir>/truth/truth.yaml
};

/// Writes the measurements (`stem`.csv), the tool the pipeline is given (`tool`: the nominal
/// one, not the truth's), the instrument and the truth. The folder appears whole or not at all:
/// the files are written into a staging folder beside it, renamed into place once all exist.
SimulationFiles write_simulation(const std::filesystem::path& dir, const std::string& stem,
                                 const SimulationResult& result, const Tool& tool,
                                 const VirtualInstrument& instrument, const TrueRobot& truth,
                                 const std::string& robot_name, const std::string& comment);

}  // namespace robcal
