#pragma once
// JPEG decoding through libjpeg(-turbo) (7-Scenes' colour images).
#include <cstddef>
#include <cstdint>
#include <string>

#include "images/image_file.h"

namespace plugslam {
namespace io {

/// True when the bytes start with a JPEG's SOI marker.
bool isJpeg(const std::uint8_t* data, std::size_t size);
/// Decodes a baseline or progressive JPEG into grey or RGB; ParseError(name) when the data is
/// corrupt or truncated (libjpeg's warnings count as errors: it would fill the rest with grey).
Image decodeJpeg(const std::uint8_t* data, std::size_t size, const std::string& name,
                 ImageChannels channels = ImageChannels::kAsStored);

}  // namespace io
}  // namespace plugslam
