#include "test_files.h"

#include <unistd.h>

#include <atomic>
#include <fstream>

namespace plugslam::test {

ScratchDir::ScratchDir() {
  static std::atomic<int> counter{0};
  path_ = std::filesystem::temp_directory_path() /
          ("plugslam_eval_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  std::filesystem::remove_all(path_);
  std::filesystem::create_directories(path_);
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string ScratchDir::write(const std::string& name, const std::string& text) const {
  const std::string p = file(name);
  std::ofstream(p) << text;
  return p;
}

}  // namespace plugslam::test
