#pragma once
// Where tests find things: the data folder ($PLUGSLAM_DATA, else ../shared/data next to the
// source tree), the build tree (plugins, binaries) and the source tree.
#include <cstdlib>
#include <string>

namespace plugslam::testing {

/// The real-data folder; may not exist (tests then skip, saying why).
inline std::string dataDir() {
  const char* env = std::getenv("PLUGSLAM_DATA");
  return env && *env ? env : PLUGSLAM_TEST_DATA_DIR;
}
/// The build tree (bin/plugslam, plugins/, tests/plugins/).
inline std::string buildDir() {
  const char* env = std::getenv("PLUGSLAM_BUILD_DIR");
  return env && *env ? env : PLUGSLAM_TEST_BUILD_DIR;
}
/// The source tree (configs/, tests/bad_input/).
inline std::string sourceDir() { return PLUGSLAM_TEST_SOURCE_DIR; }

}  // namespace plugslam::testing
