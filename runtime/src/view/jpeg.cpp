#include "view/jpeg.h"

// clang-format off
#include <cstdio>  // jpeglib.h needs FILE and size_t first
#include <jpeglib.h>
// clang-format on

#include <algorithm>
#include <vector>

#include "plugslam/errors.h"

namespace plugslam::runtime {

int viewShrinkFactor(int width) {
  int factor = 1;
  while (width / factor > kViewImageMaxWidth) ++factor;
  return factor;
}

CameraInfo viewCalibration(const CameraInfo& info) {
  const int f = viewShrinkFactor(info.width);
  if (f == 1) return info;
  // Pixel x' of the shrunk image averages source pixels f x' .. f x' + f - 1, so its centre is
  // source pixel f x' + (f - 1) / 2; the lens model (normalised coordinates) does not change.
  CameraInfo out = info;
  const double shift = 0.5 * (f - 1);
  out.fx = info.fx / f;
  out.fy = info.fy / f;
  out.cx = (info.cx - shift) / f;
  out.cy = (info.cy - shift) / f;
  out.width = info.width / f;
  out.height = std::max(1, info.height / f);
  return out;
}

std::string encodeJpeg(const Image& image, int quality) {
  const int c = image.channels;
  if ((c != 1 && c != 3) || image.width <= 0 || image.height <= 0 ||
      image.stride < image.width * c ||
      image.data.size() < static_cast<size_t>(image.stride) * static_cast<size_t>(image.height))
    throw Error("an image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                "x" + std::to_string(c) + " with stride " + std::to_string(image.stride) +
                " and " + std::to_string(image.data.size()) + " bytes cannot be encoded");
  const int factor = viewShrinkFactor(image.width);
  const int w = image.width / factor, h = std::max(1, image.height / factor);
  std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * c);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int k = 0; k < c; ++k) {
        int sum = 0, n = 0;
        for (int dy = 0; dy < factor && y * factor + dy < image.height; ++dy)
          for (int dx = 0; dx < factor; ++dx, ++n) sum += image.at(x * factor + dx, y * factor + dy, k);
        pixels[(static_cast<size_t>(y) * w + x) * c + k] = static_cast<uint8_t>(sum / std::max(n, 1));
      }

  jpeg_compress_struct cinfo;
  jpeg_error_mgr jerr;
  cinfo.err = jpeg_std_error(&jerr);
  // libjpeg's default error handler exits the process; the inputs are checked above, and
  // compressing well-formed pixels into memory cannot otherwise fail.
  jpeg_create_compress(&cinfo);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &buffer, &size);
  cinfo.image_width = static_cast<JDIMENSION>(w);
  cinfo.image_height = static_cast<JDIMENSION>(h);
  cinfo.input_components = c;
  cinfo.in_color_space = c == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = &pixels[static_cast<size_t>(cinfo.next_scanline) * w * c];
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  std::string out(reinterpret_cast<const char*>(buffer), size);
  jpeg_destroy_compress(&cinfo);
  std::free(buffer);
  return out;
}

}  // namespace plugslam::runtime
