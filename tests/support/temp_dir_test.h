#pragma once
// A gtest fixture whose every test gets a fresh folder of its own (TempDir): made before the
// test, removed with its content after it.
#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "temp_dir.h"

namespace plugslam::testing {

/// Base of the fixtures whose tests write files.
class TempDirTest : public ::testing::Test {
 protected:
  /// Each test's folder is $TMPDIR/<prefix>.XXXXXX.
  explicit TempDirTest(std::string prefix) : prefix_(std::move(prefix)) {}
  void SetUp() override {
    tmp_.emplace(prefix_);
    dir_ = tmp_->path();
  }
  void TearDown() override { tmp_.reset(); }

  /// dir_/name, as a string.
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  /// Writes `text` to dir_/name, checked; returns the path.
  std::string write(const std::string& name, const std::string& text) {
    return tmp_->write(name, text);
  }

  std::optional<TempDir> tmp_;
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace plugslam::testing
