#pragma once
// PNG files of image sequences and camera datasets: 8-bit grey / RGB images and 16-bit grey depth
// images, written with the SDK's encoder (plugslam/png.h), read through libpng.
#include <cstdint>
#include <string>
#include <vector>

#include "images/image_file.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace io {

/// A decoded PNG: 8 or 16 bits per sample, samples row-major, channels interleaved.
struct PngImage {
  int width = 0;                  ///< [px]
  int height = 0;                 ///< [px]
  int channels = 0;               ///< 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
  int bit_depth = 0;              ///< 8 or 16
  std::vector<uint16_t> samples;  ///< width * height * channels values
};

/// Writes an 8-bit grey (1 channel) or RGB (3 channels) PNG; throws InputError on failure.
void writePng(const std::string& path, const Image& image);
/// Writes a 16-bit grey PNG of width x height values; throws InputError on failure.
void writePng16(const std::string& path, int width, int height,
                const std::vector<uint16_t>& values);
/// Reads a PNG (any colour type is expanded to 8 or 16 bit samples; palette to RGB); throws
/// InputError if unreadable, ParseError if not a valid PNG.
PngImage readPng(const std::string& path);

/// True when the bytes start with the PNG signature.
bool isPng(const std::uint8_t* data, std::size_t size);
/// Decodes a PNG into an 8-bit grey or RGB Image (see ImageChannels); ParseError(name) when it
/// is corrupt, truncated or too large.
Image decodePng(const std::uint8_t* data, std::size_t size, const std::string& name,
                ImageChannels channels = ImageChannels::kAsStored);
/// A 16-bit depth code in metres, `metres_per_unit` each: 0 and 65535 (the "no reading" codes of
/// TUM, 7-Scenes and the Kinect drivers) become 0, the one rule for PNG files and bag messages.
inline float depthFromUnits(std::uint16_t v, float metres_per_unit) {
  return (v == 0 || v == 65535) ? 0.0f : static_cast<float>(v) * metres_per_unit;
}

/// Decodes a 16-bit single-channel PNG whose values are depths in 1/units_per_metre metres;
/// 0 and 65535 (the "no reading" codes of TUM, 7-Scenes and the Kinect drivers) become 0.
/// Throws ParseError(name) for anything else (8-bit or colour PNGs included).
DepthImage decodeDepthPng(const std::uint8_t* data, std::size_t size, const std::string& name,
                          double units_per_metre);

/// Depth in metres to 16-bit TUM units (scale per metre, 0 = no reading, too far = 0).
std::vector<uint16_t> depthToUint16(const DepthImage& depth, double scale = 5000.0);

}  // namespace io
}  // namespace plugslam
