// PNG reading and writing refuse bad files with typed errors.
#include "images/png.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "plugslam/errors.h"
#include "temp_dir.h"

namespace plugslam::io {
namespace {

namespace fs = std::filesystem;

TEST(Png, ReadAndWriteErrors) {
  EXPECT_THROW(readPng("/nonexistent/x.png"), InputError);
  const plugslam::testing::TempDir tmp("plugslam_png");
  const fs::path dir = tmp.path();
  std::ofstream(dir / "bad.png") << "not a png at all";
  EXPECT_THROW(readPng((dir / "bad.png").string()), ParseError);
  // A truncated PNG.
  Image im;
  im.resize(50, 40, 3);
  writePng((dir / "ok.png").string(), im);
  const auto size = fs::file_size(dir / "ok.png");
  fs::resize_file(dir / "ok.png", size / 2);
  EXPECT_THROW(readPng((dir / "ok.png").string()), ParseError);
  Image two;
  two.resize(4, 4, 2);
  EXPECT_THROW(writePng((dir / "two.png").string(), two), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace plugslam::io
