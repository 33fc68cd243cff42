// The test helpers of tests/support.
// Item 17.23: the data folder is read when a test runs, so `PLUGSLAM_DATA=/elsewhere ctest` reads
// /elsewhere (ctest_keeps_the_users_data_folder in CMakeLists.txt runs this under ctest).
#include "test_paths.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "temp_dir.h"

TEST(TestPaths, DataFolderComesFromTheEnvironment) {
  const char* before = std::getenv("PLUGSLAM_DATA");
  const std::string saved = before ? before : "";
  // What the test sees as it runs (the outer ctest test matches this line).
  std::cout << "data folder: " << plugslam::testing::dataDir() << "\n";
  ::setenv("PLUGSLAM_DATA", "/somewhere/else", 1);
  EXPECT_EQ(plugslam::testing::dataDir(), "/somewhere/else");
  ::unsetenv("PLUGSLAM_DATA");
  const char* configured = std::getenv("PLUGSLAM_TEST_DATA_DEFAULT");
  EXPECT_EQ(plugslam::testing::dataDir(),
            configured && *configured ? std::string(configured)
                                      : plugslam::testing::sourceDir() + "/../shared/data");
  if (!saved.empty()) ::setenv("PLUGSLAM_DATA", saved.c_str(), 1);
}

// Item 17.22: every test writes under a folder of its own: fresh, distinct, removed after.
TEST(TempDir, IsFreshOfItsOwnAndRemovedAfter) {
  std::filesystem::path kept;
  {
    const plugslam::testing::TempDir a("plugslam_tempdir_test"), b("plugslam_tempdir_test");
    EXPECT_NE(a.path(), b.path());
    EXPECT_TRUE(std::filesystem::is_directory(a.path()));
    EXPECT_TRUE(std::filesystem::is_empty(a.path()));
    const std::string file = a.write("sub/x.txt", "hello");
    EXPECT_EQ(file, a.file("sub/x.txt"));
    EXPECT_EQ(std::filesystem::file_size(file), 5u);
    kept = a.path();
    // A write that cannot happen throws rather than leaving an old file to be read by luck.
    EXPECT_THROW(a.write("sub/x.txt/y", "no"), std::exception);
  }
  EXPECT_FALSE(std::filesystem::exists(kept));
}
