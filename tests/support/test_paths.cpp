#include "test_paths.h"

#include <cstdlib>

namespace plugslam::testing {

std::string sourceDir() { return PLUGSLAM_TEST_SOURCE_DIR; }

std::string dataDir() {
  for (const char* name : {"PLUGSLAM_DATA", "PLUGSLAM_TEST_DATA_DEFAULT"}) {
    const char* env = std::getenv(name);
    if (env && *env) return env;
  }
  return sourceDir() + "/../shared/data";
}

std::string buildDir() {
  const char* env = std::getenv("PLUGSLAM_BUILD_DIR");
  return env && *env ? env : PLUGSLAM_TEST_BUILD_DIR;
}

}  // namespace plugslam::testing
