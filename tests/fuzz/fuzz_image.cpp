// PNG / JPEG image and 16-bit PNG depth decoding (images/image_file, images/png). The first byte picks the
// decoder: 0 as stored, 1 grey, 2 RGB, 3 depth; the rest is the file.
#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "images/image_file.h"
#include "images/png.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::uint8_t mode = data[0] % 4;
  try {
    if (mode == 3) {
      plugslam::io::decodeDepthPng(data + 1, size - 1, "fuzz.png", 5000.0);
    } else {
      const auto channels = mode == 0   ? plugslam::io::ImageChannels::kAsStored
                            : mode == 1 ? plugslam::io::ImageChannels::kGrey
                                        : plugslam::io::ImageChannels::kRgb;
      plugslam::io::decodeImage(data + 1, size - 1, "fuzz.img", channels);
    }
  } catch (const plugslam::Error&) {
  }
  return 0;
}
