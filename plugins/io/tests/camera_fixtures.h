#pragma once
// Small camera datasets written by the tests into their own temporary folders: PNG and JPEG
// files through libpng and libjpeg directly (independent of the readers under test), and text.
#include <gtest/gtest.h>
#include <jpeglib.h>
#include <png.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace plugslam::io::testing {

/// A fresh folder for one test (tests/support/temp_dir.h), removed by its destructor.
class TempFolder {
 public:
  /// The folder.
  const std::filesystem::path& path() const { return dir_.path(); }
  /// path() / relative, as a string.
  std::string operator/(const std::string& relative) const {
    return (dir_.path() / relative).string();
  }

 private:
  ::plugslam::testing::TempDir dir_{"plugslam_camera"};
};

/// Writes text, creating the folders on the way.
inline void writeText(const std::string& path, const std::string& text) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

/// Writes raw bytes, creating the folders on the way.
inline void writeBytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// Reads a whole file.
inline std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

/// A PNG of w x h samples per channel (8 or 16 bits; 16-bit samples as host integers).
/// color_type is libpng's (PNG_COLOR_TYPE_GRAY, _RGB, _RGB_ALPHA, ...).
inline void writePngFile(const std::string& path, int w, int h, int color_type, int bit_depth,
                         const std::vector<std::uint16_t>& samples) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr) << path;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), bit_depth,
               color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  const int channels = png_get_channels(png, info);
  const std::size_t row_samples = static_cast<std::size_t>(w) * channels;
  std::vector<std::uint8_t> row(row_samples * (bit_depth == 16 ? 2 : 1));
  for (int y = 0; y < h; ++y) {
    for (std::size_t i = 0; i < row_samples; ++i) {
      const std::uint16_t v = samples[static_cast<std::size_t>(y) * row_samples + i];
      if (bit_depth == 16) {
        row[2 * i] = static_cast<std::uint8_t>(v >> 8);  // PNG is big-endian
        row[2 * i + 1] = static_cast<std::uint8_t>(v & 255);
      } else {
        row[i] = static_cast<std::uint8_t>(v);
      }
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

/// An 8-bit grey or RGB PNG with a pattern that depends on (x, y, c) and `seed`.
inline void writePatternPng(const std::string& path, int w, int h, int channels, int seed = 0) {
  std::vector<std::uint16_t> s(static_cast<std::size_t>(w) * h * channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c)
        s[(static_cast<std::size_t>(y) * w + x) * channels + c] =
            static_cast<std::uint16_t>((x * 7 + y * 13 + c * 61 + seed * 29) & 255);
  writePngFile(path, w, h, channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB, 8, s);
}

/// A 16-bit depth PNG with every pixel `value`.
inline void writeDepthPng(const std::string& path, int w, int h, std::uint16_t value) {
  writePngFile(path, w, h, PNG_COLOR_TYPE_GRAY, 16,
               std::vector<std::uint16_t>(static_cast<std::size_t>(w) * h, value));
}

/// A baseline JPEG (quality 95) of an 8-bit grey or RGB pattern; returns the pixels written.
inline std::vector<std::uint8_t> writeJpegFile(const std::string& path, int w, int h,
                                               int channels) {
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * h * channels);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < channels; ++c)  // smooth, so JPEG keeps it within a few levels
        pixels[(static_cast<std::size_t>(y) * w + x) * channels + c] =
            static_cast<std::uint8_t>(40 + x + 2 * y + 30 * c);
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  FILE* f = std::fopen(path.c_str(), "wb");
  EXPECT_NE(f, nullptr) << path;
  if (!f) return pixels;
  jpeg_compress_struct cinfo;
  jpeg_error_mgr err;
  cinfo.err = jpeg_std_error(&err);
  jpeg_create_compress(&cinfo);
  jpeg_stdio_dest(&cinfo, f);
  cinfo.image_width = static_cast<JDIMENSION>(w);
  cinfo.image_height = static_cast<JDIMENSION>(h);
  cinfo.input_components = channels;
  cinfo.in_color_space = channels == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, 95, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = &pixels[static_cast<std::size_t>(cinfo.next_scanline) * w * channels];
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  std::fclose(f);
  return pixels;
}

}  // namespace plugslam::io::testing
