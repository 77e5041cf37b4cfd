#pragma once
// The read-only external reference data of the cross-checks (public data read in place, never
// copied into the project): one search for every test that uses it (test_support.cpp).

#include <filesystem>
#include <optional>
#include <string>

namespace robcal::test {

/// A file of the external reference data, by its path inside that folder.
struct ExternalFile {
  std::optional<std::filesystem::path> path;  ///< nullopt when not found
  std::string searched;                       ///< the places looked at, one per line
};

/// Looks in $ROBCAL_EXTERNAL_DATA_DIR, else in shared/data/external beside the source tree or
/// one of its parents (CI keeps shared/ beside the clone): the first that holds the file.
ExternalFile find_external_data(const std::filesystem::path& relative);

}  // namespace robcal::test
