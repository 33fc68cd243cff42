#pragma once
// A test's own temporary folder: fresh (mkdtemp under $TMPDIR, else /tmp), so two users or two
// runs never share a file, and removed with its content when the test ends. Writes through it are
// checked, so a test never reads an older file by luck.
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace plugslam::testing {

/// A fresh temporary folder, removed (with everything in it) on destruction.
class TempDir {
 public:
  /// Creates $TMPDIR/<prefix>.XXXXXX; throws std::runtime_error if it cannot.
  explicit TempDir(const std::string& prefix = "plugslam_test") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + ".XXXXXX")).string();
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    if (::mkdtemp(buf.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary folder like " + pattern);
    path_ = buf.data();
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// The folder.
  const std::filesystem::path& path() const { return path_; }
  /// path()/name, as a string.
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  /// Writes `text` to path()/name (creating parent folders), checks the write, returns the path.
  std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path p = path_ / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw std::runtime_error("cannot write " + p.string());
    return p.string();
  }

 private:
  std::filesystem::path path_;
};

}  // namespace plugslam::testing
