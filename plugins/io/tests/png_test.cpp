// PNG reading and writing refuse bad files with typed errors.
#include "images/png.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

// Images go through the one atomic writer: the decoded samples are the ones written, an
// overwrite leaves only the new file, and an unwritable target names the target, leaving nothing.
TEST(Png, WritesAtomicallyAndReadsBackExactly) {
  const plugslam::testing::TempDir tmp("plugslam_png");
  const fs::path& dir = tmp.path();
  Image rgb;
  rgb.resize(7, 5, 3);
  for (size_t i = 0; i < rgb.data.size(); ++i) rgb.data[i] = static_cast<uint8_t>(i * 37);
  const std::string path = (dir / "rgb.png").string();
  writePng(path, rgb);
  Image grey;
  grey.resize(3, 2, 1);
  writePng(path, grey);  // over the first: only the new image remains
  PngImage back = readPng(path);
  EXPECT_EQ(back.width, 3);
  EXPECT_EQ(back.channels, 1);
  writePng(path, rgb);
  back = readPng(path);
  ASSERT_EQ(back.samples.size(), rgb.data.size());
  for (size_t i = 0; i < rgb.data.size(); ++i) EXPECT_EQ(back.samples[i], rgb.data[i]) << i;
  const std::vector<uint16_t> depth{0, 1, 255, 256, 40000, 65535};
  writePng16((dir / "depth.png").string(), 3, 2, depth);
  back = readPng((dir / "depth.png").string());
  EXPECT_EQ(back.bit_depth, 16);
  EXPECT_EQ(back.samples, depth);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"depth.png", "rgb.png"}));
  const std::string missing = (dir / "missing" / "x.png").string();
  try {
    writePng(missing, rgb);
    ADD_FAILURE() << "no error writing into a missing folder";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'" + missing + "'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "missing"));
}

}  // namespace
}  // namespace plugslam::io
