#pragma once
// Image files of camera datasets: PNG (images/png.h) and JPEG (images/jpeg.h) colour or grey
// images, and 16-bit PNG depth images. Decoding works on bytes in memory, so the fuzz targets
// reach it without files; the file functions read the whole file first.
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

/// ParseError(name) unless width x height is a non-empty image of at most kMaxImagePixels.
void checkImageSize(const std::string& name, std::size_t width, std::size_t height);

/// Decodes a PNG or a JPEG (told apart by their signatures); `name` appears in messages. Throws
/// ParseError(name) when the bytes are not a complete, valid image of either kind.
Image decodeImage(const std::uint8_t* data, std::size_t size, const std::string& name,
                  ImageChannels channels = ImageChannels::kAsStored);

/// Reads a whole file; InputError naming it when it is missing or cannot be read.
std::vector<std::uint8_t> readFileBytes(const std::string& path);
/// readFileBytes + decodeImage.
Image readImageFile(const std::string& path, ImageChannels channels = ImageChannels::kAsStored);
/// readFileBytes + decodeDepthPng (images/png.h).
DepthImage readDepthFile(const std::string& path, double units_per_metre);

}  // namespace io
}  // namespace plugslam
