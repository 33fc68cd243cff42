#pragma once
// Where tests find things: the data folder, the build tree (plugins, binaries) and the source
// tree. The data folder is looked up when the test runs, never compiled in: $PLUGSLAM_DATA, else
// the value the build was configured with ($PLUGSLAM_TEST_DATA_DEFAULT, set by CTest), else
// ../shared/data beside the source tree.
#include <cstdlib>
#include <string>

namespace plugslam::testing {

/// The source tree (configs/, tests/bad_input/).
inline std::string sourceDir() { return PLUGSLAM_TEST_SOURCE_DIR; }
/// The real-data folder; may not exist (tests then skip, saying why).
inline std::string dataDir() {
  for (const char* name : {"PLUGSLAM_DATA", "PLUGSLAM_TEST_DATA_DEFAULT"}) {
    const char* env = std::getenv(name);
    if (env && *env) return env;
  }
  return sourceDir() + "/../shared/data";
}
/// The build tree (bin/plugslam, plugins/, tests/plugins/).
inline std::string buildDir() {
  const char* env = std::getenv("PLUGSLAM_BUILD_DIR");
  return env && *env ? env : PLUGSLAM_TEST_BUILD_DIR;
}

}  // namespace plugslam::testing
