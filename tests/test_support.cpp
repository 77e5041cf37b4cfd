#include "test_support.hpp"
#include "test_external_data.hpp"

#include <cstdlib>

namespace robcal::test {

// The only test source that knows where the tree is (CMakeLists gives it the path).
std::string data_path(const std::string& relative) {
  return std::string(ROBCAL_TEST_DATA_DIR) + "/" + relative;
}

ExternalFile find_external_data(const std::filesystem::path& relative) {
  std::vector<std::filesystem::path> folders;
  if (const char* env = std::getenv("ROBCAL_EXTERNAL_DATA_DIR")) folders.emplace_back(env);
  // The source tree (above tests/data) and its parents.
  const std::filesystem::path tests_data =
      std::filesystem::absolute(data_path("")).lexically_normal().parent_path();
  for (std::filesystem::path dir = tests_data.parent_path().parent_path(); dir.has_relative_path();
       dir = dir.parent_path())
    folders.push_back(dir / "shared" / "data" / "external");
  ExternalFile found;
  for (const std::filesystem::path& folder : folders) {
    if (std::filesystem::exists(folder / relative)) {
      found.path = folder / relative;
      return found;
    }
    found.searched += "\n  " + (folder / relative).string();
  }
  return found;
}

}  // namespace robcal::test
