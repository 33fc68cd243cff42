#pragma once
// The pixels of a drawn figure, and PNG files of them: what `plugslam render` writes and what its
// tests read back.
#include <cstdint>
#include <string>
#include <vector>

namespace plugslam::runtime::render {

/// An 8-bit RGB colour.
struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

/// A width x height RGB image, row-major from the top-left corner, 3 samples per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> samples;

  /// The pixel at (x, y); (x, y) must be inside.
  Rgb at(int x, int y) const {
    const size_t i = (static_cast<size_t>(y) * width + x) * 3;
    return {samples[i], samples[i + 1], samples[i + 2]};
  }
};

/// Encodes the image as an 8-bit sRGB PNG (the SDK's encoder).
std::string encodePng(const RgbImage& image);
/// Writes the image as a PNG atomically; throws InputError on failure.
void writePng(const std::string& path, const RgbImage& image);
/// Reads any PNG as RGB (grey expanded, alpha composed on black, 16 bit reduced); throws
/// InputError if the file cannot be read or is not a valid PNG.
RgbImage readPng(const std::string& path);

}  // namespace plugslam::runtime::render
