#pragma once
// The one PNG encoder of plugslam (maps, pictures, image sequences). libpng stays inside the SDK.
#include <cstddef>
#include <cstdint>
#include <string>

namespace plugslam {
inline namespace abi_v1 {

/// Pixels to encode: `height` rows `stride` bytes apart, each of `width` pixels of `channels`
/// samples (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA), `bit_depth` 8 or 16 bits per sample (16-bit
/// samples in the host's byte order). Not owned.
struct PngPixels {
  const uint8_t* data = nullptr;  ///< the first row
  int width = 0;                  ///< [px]
  int height = 0;                 ///< [px]
  int channels = 1;               ///< samples per pixel
  int bit_depth = 8;              ///< bits per sample: 8 or 16
  size_t stride = 0;              ///< bytes from one row to the next (0: packed rows)
};

/// How to encode. The defaults are libpng's (and zlib's).
struct PngOptions {
  int level = 6;            ///< zlib level, 0 (store) .. 9 (smallest); 1 for long image sequences
  bool filters = true;      ///< libpng's adaptive row filters (smaller for photos and plots)
  bool srgb = false;        ///< an sRGB chunk: colours meant for a screen (pictures, plots)
  size_t idat_bytes = 8192;  ///< bytes of compressed data per IDAT chunk (0: one chunk)
};

/// The bytes of a PNG file holding `pixels`; throws InputError on bad dimensions, Error when
/// libpng fails.
std::string encodePng(const PngPixels& pixels, const PngOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
