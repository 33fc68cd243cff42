#pragma once
// A scratch folder per test, removed afterwards.
#include <filesystem>
#include <string>

namespace plugslam::test {

/// A fresh empty folder under the system temp dir, deleted with the object.
class ScratchDir {
 public:
  ScratchDir();
  ~ScratchDir();
  /// Path of a file inside the folder.
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Writes text to a file inside the folder and returns its path.
  std::string write(const std::string& name, const std::string& text) const;
  /// The folder.
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace plugslam::test
