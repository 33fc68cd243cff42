#pragma once
// Where tests find things: the data folder, the build tree (plugins, binaries) and the source
// tree. The data folder is looked up when the test runs, never compiled in: $PLUGSLAM_DATA, else
// the value the build was configured with ($PLUGSLAM_TEST_DATA_DEFAULT, set by CTest), else
// ../shared/data beside the source tree. The source and build folders are compiled into
// test_paths.cpp alone, so the test objects are the same in every checkout and share ccache.
#include <string>

namespace plugslam::testing {

/// The source tree (configs/, tests/bad_input/).
std::string sourceDir();
/// The real-data folder; may not exist (tests then skip, saying why).
std::string dataDir();
/// The build tree (bin/plugslam, plugins/, tests/plugins/).
std::string buildDir();

}  // namespace plugslam::testing
