// PNG and JPEG decoding for the camera sources: layouts, conversions, depth units, and every
// kind of bad file giving a ParseError that names it.
#include "images/image_file.h"

#include <gtest/gtest.h>

#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <string>

#include "camera_fixtures.h"
#include "plugslam/errors.h"

namespace plugslam::io {
namespace {

using testing::TempFolder;

std::string parseErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ParseError& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("not a ParseError: ") + e.what();
  }
  return "no error";
}

TEST(ImageFile, GreyAndRgbPngKeepTheirPixels) {
  TempFolder dir;
  testing::writePatternPng(dir / "g.png", 5, 3, 1, 1);
  testing::writePatternPng(dir / "c.png", 4, 2, 3, 2);
  const Image g = readImageFile(dir / "g.png");
  ASSERT_EQ(g.width, 5);
  ASSERT_EQ(g.height, 3);
  ASSERT_EQ(g.channels, 1);
  EXPECT_EQ(g.stride, 5);
  EXPECT_EQ(g.at(4, 2), (4 * 7 + 2 * 13 + 29) & 255);
  const Image c = readImageFile(dir / "c.png");
  ASSERT_EQ(c.channels, 3);
  EXPECT_EQ(c.at(3, 1, 2), (3 * 7 + 13 + 2 * 61 + 2 * 29) & 255);
}

TEST(ImageFile, ConversionsToGreyAndRgb) {
  TempFolder dir;
  // One RGB pixel (200, 100, 50): BT.601 luma 0.299*200 + 0.587*100 + 0.114*50 = 124.2.
  testing::writePngFile(dir / "p.png", 1, 1, PNG_COLOR_TYPE_RGB, 8, {200, 100, 50});
  const Image grey = readImageFile(dir / "p.png", ImageChannels::kGrey);
  ASSERT_EQ(grey.channels, 1);
  EXPECT_NEAR(grey.at(0, 0), 124, 1);
  testing::writePngFile(dir / "g.png", 2, 1, PNG_COLOR_TYPE_GRAY, 8, {9, 250});
  const Image rgb = readImageFile(dir / "g.png", ImageChannels::kRgb);
  ASSERT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.at(1, 0, 0), 250);
  EXPECT_EQ(rgb.at(1, 0, 2), 250);
}

TEST(ImageFile, AlphaAndSixteenBitColourAreReducedToEightBitRgb) {
  TempFolder dir;
  testing::writePngFile(dir / "a.png", 1, 1, PNG_COLOR_TYPE_RGB_ALPHA, 8, {10, 20, 30, 7});
  const Image a = readImageFile(dir / "a.png");
  ASSERT_EQ(a.channels, 3);
  EXPECT_EQ(a.at(0, 0, 1), 20);
  testing::writePngFile(dir / "w.png", 1, 1, PNG_COLOR_TYPE_RGB, 16, {0x1234, 0xFF00, 0x0100});
  const Image w = readImageFile(dir / "w.png");
  ASSERT_EQ(w.channels, 3);
  EXPECT_EQ(w.at(0, 0, 0), 0x12);
  EXPECT_EQ(w.at(0, 0, 1), 0xFF);
}

TEST(ImageFile, JpegDecodesCloseToItsSource) {
  TempFolder dir;
  const auto rgb = testing::writeJpegFile(dir / "c.jpg", 32, 16, 3);
  const Image c = readImageFile(dir / "c.jpg");
  ASSERT_EQ(c.width, 32);
  ASSERT_EQ(c.height, 16);
  ASSERT_EQ(c.channels, 3);
  // Quality 95 on a smooth ramp: measured max error 2 grey levels; 6 leaves room for other
  // libjpeg builds and still fails on a channel swap or a misplaced row.
  int worst = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) worst = std::max(worst, std::abs(c.data[i] - rgb[i]));
  EXPECT_LE(worst, 6);
  const Image g = readImageFile(dir / "c.jpg", ImageChannels::kGrey);
  EXPECT_EQ(g.channels, 1);
  testing::writeJpegFile(dir / "g.jpg", 8, 8, 1);
  EXPECT_EQ(readImageFile(dir / "g.jpg").channels, 1);
  EXPECT_EQ(readImageFile(dir / "g.jpg", ImageChannels::kRgb).channels, 3);
}

TEST(ImageFile, DepthPngInMetresWithNoReadingCodes) {
  TempFolder dir;
  testing::writePngFile(dir / "d.png", 4, 1, PNG_COLOR_TYPE_GRAY, 16, {0, 5000, 12345, 65535});
  const DepthImage tum = readDepthFile(dir / "d.png", 5000.0);
  ASSERT_EQ(tum.width, 4);
  EXPECT_EQ(tum.at(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(tum.at(1, 0), 1.0f);
  EXPECT_FLOAT_EQ(tum.at(2, 0), 12345.0f / 5000.0f);
  EXPECT_EQ(tum.at(3, 0), 0.0f);  // 65535: no reading (7-Scenes)
  const DepthImage mm = readDepthFile(dir / "d.png", 1000.0);
  EXPECT_FLOAT_EQ(mm.at(1, 0), 5.0f);
}

TEST(ImageFile, BadFilesAreParseErrorsNamingTheFile) {
  TempFolder dir;
  testing::writePatternPng(dir / "ok.png", 16, 16, 3);
  const auto png = testing::readBytes(dir / "ok.png");
  testing::writeJpegFile(dir / "ok.jpg", 16, 16, 3);
  const auto jpg = testing::readBytes(dir / "ok.jpg");

  auto cut = [&](std::vector<std::uint8_t> b, std::size_t n) {
    b.resize(n);
    return b;
  };
  testing::writeBytes(dir / "truncated.png", cut(png, png.size() / 2));
  std::vector<std::uint8_t> flipped = png;
  flipped[40] ^= 0xFF;  // inside IHDR / IDAT: a CRC or zlib error
  testing::writeBytes(dir / "flipped.png", flipped);
  testing::writeBytes(dir / "truncated.jpg", cut(jpg, jpg.size() / 2));
  testing::writeBytes(dir / "header.jpg", cut(jpg, 40));
  testing::writeBytes(dir / "text.png", {'h', 'e', 'l', 'l', 'o'});
  testing::writeBytes(dir / "empty.png", {});

  const std::string t = parseErrorOf([&] { readImageFile(dir / "truncated.png"); });
  EXPECT_NE(t.find("truncated.png"), std::string::npos) << t;
  EXPECT_NE(t.find("corrupt PNG"), std::string::npos) << t;
  EXPECT_NE(parseErrorOf([&] { readImageFile(dir / "flipped.png"); }).find("corrupt PNG"),
            std::string::npos);
  const std::string j = parseErrorOf([&] { readImageFile(dir / "truncated.jpg"); });
  EXPECT_NE(j.find("truncated.jpg"), std::string::npos) << j;
  EXPECT_NE(j.find("corrupt JPEG"), std::string::npos) << j;
  EXPECT_NE(parseErrorOf([&] { readImageFile(dir / "header.jpg"); }).find("corrupt JPEG"),
            std::string::npos);
  EXPECT_NE(parseErrorOf([&] { readImageFile(dir / "text.png"); }).find("not a PNG or JPEG"),
            std::string::npos);
  EXPECT_NE(parseErrorOf([&] { readImageFile(dir / "empty.png"); }).find("empty file"),
            std::string::npos);
  try {
    readImageFile(dir / "missing.png");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing.png"), std::string::npos) << e.what();
  }
}

TEST(ImageFile, DepthMustBeSixteenBitGrey) {
  TempFolder dir;
  testing::writePatternPng(dir / "eight.png", 4, 4, 1);
  testing::writePatternPng(dir / "rgb.png", 4, 4, 3);
  testing::writeJpegFile(dir / "d.jpg", 8, 8, 1);
  EXPECT_NE(parseErrorOf([&] { readDepthFile(dir / "eight.png", 1000); })
                .find("depth image is 8-bit grey, expected a 16-bit grey PNG"),
            std::string::npos);
  EXPECT_NE(parseErrorOf([&] { readDepthFile(dir / "rgb.png", 1000); }).find("8-bit RGB"),
            std::string::npos);
  EXPECT_NE(parseErrorOf([&] { readDepthFile(dir / "d.jpg", 1000); }).find("not a PNG"),
            std::string::npos);
}

TEST(ImageFile, HugeDeclaredSizeIsRefusedBeforeAllocating) {
  // A valid PNG header claiming 60000 x 60000 RGB (10.8 GB decoded), then nothing.
  TempFolder dir;
  testing::writePatternPng(dir / "ok.png", 1, 1, 3);
  auto b = testing::readBytes(dir / "ok.png");
  // IHDR width/height at bytes 16..23; the CRC after them is now wrong, so patch it too.
  const std::uint32_t side = 60000;
  for (int k = 0; k < 4; ++k) b[16 + k] = b[20 + k] = static_cast<std::uint8_t>(side >> (24 - 8 * k));
  const std::uint32_t crc = static_cast<std::uint32_t>(crc32(0, b.data() + 12, 17));
  for (int k = 0; k < 4; ++k) b[29 + k] = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
  testing::writeBytes(dir / "huge.png", b);
  const std::string e = parseErrorOf([&] { readImageFile(dir / "huge.png"); });
  EXPECT_NE(e.find("larger than"), std::string::npos) << e;
}

}  // namespace
}  // namespace plugslam::io
