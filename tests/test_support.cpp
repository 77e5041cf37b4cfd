#include "test_support.hpp"

namespace robcal::test {

// The only test source that knows where the tree is (CMakeLists gives it the path).
std::string data_path(const std::string& relative) {
  return std::string(ROBCAL_TEST_DATA_DIR) + "/" + relative;
}

}  // namespace robcal::test
