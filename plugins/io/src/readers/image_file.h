#pragma once
// Image files of camera datasets: PNG (libpng) and JPEG (libjpeg-turbo) colour or grey images,
// and 16-bit PNG depth images. Decoding works on bytes in memory, so the fuzz targets reach it
// without files; the file functions read the whole file first.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"

namespace plugslam {
namespace io {

/// The channel layout a decoded image is converted to.
enum class ImageChannels {
  kAsStored,  ///< grey stays grey, colour becomes RGB (alpha dropped, 16 bits to 8)
  kGrey,      ///< one channel (colour converted with the ITU-R BT.601 weights)
  kRgb,       ///< three channels (grey replicated)
};

/// Largest image accepted, in pixels (a corrupt header must not ask for gigabytes).
constexpr std::size_t kMaxImagePixels = std::size_t{1} << 26;

/// Decodes a PNG or a JPEG (told apart by their signatures); `name` appears in messages. Throws
/// ParseError(name) when the bytes are not a complete, valid image of either kind.
Image decodeImage(const std::uint8_t* data, std::size_t size, const std::string& name,
                  ImageChannels channels = ImageChannels::kAsStored);
/// Decodes a 16-bit single-channel PNG whose values are depths in 1/units_per_metre metres;
/// 0 and 65535 (the "no reading" codes of TUM, 7-Scenes and the Kinect drivers) become 0.
/// Throws ParseError(name) for anything else (8-bit or colour PNGs included).
DepthImage decodeDepthPng(const std::uint8_t* data, std::size_t size, const std::string& name,
                          double units_per_metre);

/// Reads a whole file; InputError naming it when it is missing or cannot be read.
std::vector<std::uint8_t> readFileBytes(const std::string& path);
/// readFileBytes + decodeImage.
Image readImageFile(const std::string& path, ImageChannels channels = ImageChannels::kAsStored);
/// readFileBytes + decodeDepthPng.
DepthImage readDepthFile(const std::string& path, double units_per_metre);

}  // namespace io
}  // namespace plugslam
