#pragma once
// A fresh temporary folder of a test's own (tests never write fixed names in /tmp), removed with
// everything in it when the object goes.
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace plugslam::testing {

/// mkdtemp'd folder `<tmp>/<prefix>XXXXXX`, removed on destruction.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& prefix = "plugslam-test-") {
    std::string t = (std::filesystem::temp_directory_path() / (prefix + "XXXXXX")).string();
    if (!mkdtemp(t.data())) throw std::runtime_error("cannot make a temporary folder " + t);
    path = t;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
};

}  // namespace plugslam::testing
