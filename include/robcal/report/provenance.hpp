#pragma once
/// \file
/// Where a result came from, for the report (and whoever reads it later): robcal's version, the
/// date, the command line, every input file with its SHA-256 (FIPS 180-4), the instrument and
/// its σ, the robot, the calibration level and the seed.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace YAML {  // NOLINT(readability-identifier-naming): yaml-cpp's namespace
class Emitter;
}

namespace robcal {

struct ProvenanceFile {
  std::string role;  ///< "model", "validation", "calibration"…
  std::string path;
  std::string sha256;  ///< lowercase hex
};

struct Provenance {
  std::string robcal_version;
  std::string date_utc;  ///< ISO 8601, e.g. 2026-11-24T21:40:37Z
  std::string command_line;
  std::vector<ProvenanceFile> files;
  std::string instrument;                     ///< empty: not given
  std::optional<double> instrument_sigma_mm;  ///< per axis
  std::string robot, level;
  std::optional<unsigned long long> seed;
};

/// robcal's version (the CMake project version).
std::string robcal_version();

/// The current time, UTC, ISO 8601 to the second.
std::string utc_now();

/// SHA-256 of `bytes` as 64 lowercase hex digits.
std::string sha256_hex(std::string_view bytes);

/// A file's role, path and SHA-256 (InputError naming the file when it cannot be read).
ProvenanceFile provenance_file(const std::string& role, const std::string& path);

/// The version, the date now and the command line `argv` joined by spaces (arguments with
/// blanks quoted).
Provenance start_provenance(int argc, const char* const* argv);

/// start_provenance with this process's command line (/proc/self/cmdline; empty elsewhere).
Provenance start_provenance_of_process();

nlohmann::json provenance_json(const Provenance& provenance);

/// The same as a YAML block map into `out` (what `robcal calibrate` writes under
/// statistics.provenance of the model file).
void emit_provenance(YAML::Emitter& out, const Provenance& provenance);

}  // namespace robcal
