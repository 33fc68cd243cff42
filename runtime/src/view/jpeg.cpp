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

namespace {

bool consistent(const Image& image) {
  const int c = image.channels;
  return (c == 1 || c == 3) && image.width > 0 && image.height > 0 &&
         image.stride >= image.width * c &&
         image.data.size() >= static_cast<size_t>(image.stride) * static_cast<size_t>(image.height);
}

// `image` averaged down by `factor` into `out` (w x h, stride w c): each output pixel is the
// rounded mean of its factor x factor block.
void shrink(const Image& image, int factor, Image& out) {
  const int c = image.channels;
  const int w = image.width / factor, h = std::max(1, image.height / factor);
  out.stamp = image.stamp;
  out.width = w;
  out.height = h;
  out.channels = c;
  out.stride = w * c;
  out.data.resize(static_cast<size_t>(out.stride) * h);
  const size_t stride = static_cast<size_t>(image.stride);
  const int rows = std::min(factor, image.height);  // a 1-row image shrinks along x only
  if (factor == 2 && rows == 2) {
    // The common case (KITTI's 1241 px, 1280 px cameras): two rows at a time, no inner loops.
    for (int y = 0; y < h; ++y) {
      const uint8_t* a = &image.data[2 * static_cast<size_t>(y) * stride];
      const uint8_t* b = a + stride;
      uint8_t* o = &out.data[static_cast<size_t>(y) * out.stride];
      if (c == 1) {
        for (int x = 0; x < w; ++x)
          o[x] = static_cast<uint8_t>((a[2 * x] + a[2 * x + 1] + b[2 * x] + b[2 * x + 1] + 2) >> 2);
      } else {
        for (int x = 0; x < w; ++x)
          for (int k = 0; k < 3; ++k) {
            const int i = 6 * x + k;
            o[3 * x + k] = static_cast<uint8_t>((a[i] + a[i + 3] + b[i] + b[i + 3] + 2) >> 2);
          }
      }
    }
    return;
  }
  std::vector<int> sums(static_cast<size_t>(w) * c);
  const int n = rows * factor;
  for (int y = 0; y < h; ++y) {
    std::fill(sums.begin(), sums.end(), 0);
    for (int dy = 0; dy < rows; ++dy) {
      const uint8_t* row = &image.data[(static_cast<size_t>(y) * factor + dy) * stride];
      for (int x = 0; x < w; ++x)
        for (int dx = 0; dx < factor; ++dx)
          for (int k = 0; k < c; ++k)
            sums[static_cast<size_t>(x) * c + k] += row[(x * factor + dx) * c + k];
    }
    uint8_t* o = &out.data[static_cast<size_t>(y) * out.stride];
    for (size_t i = 0; i < sums.size(); ++i) o[i] = static_cast<uint8_t>((sums[i] + n / 2) / n);
  }
}

}  // namespace

Image viewImage(const Image& image) {
  if (!consistent(image)) return image;
  const int factor = viewShrinkFactor(image.width);
  if (factor == 1) return image;
  Image out;
  shrink(image, factor, out);
  return out;
}

std::string encodeJpeg(const Image& image, int quality) {
  const int c = image.channels;
  if (!consistent(image))
    throw Error("an image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                "x" + std::to_string(c) + " with stride " + std::to_string(image.stride) +
                " and " + std::to_string(image.data.size()) + " bytes cannot be encoded");
  // Already at the viewers' size (viewImage on the run's thread): compressed from its rows.
  Image shrunk;
  const bool small = viewShrinkFactor(image.width) == 1;
  if (!small) shrink(image, viewShrinkFactor(image.width), shrunk);
  const Image& pixels = small ? image : shrunk;
  const int w = pixels.width, h = pixels.height;

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
    // libjpeg reads the row; its API takes a non-const pointer.
    JSAMPROW row = const_cast<uint8_t*>(
        &pixels.data[static_cast<size_t>(cinfo.next_scanline) * static_cast<size_t>(pixels.stride)]);
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  std::string out(reinterpret_cast<const char*>(buffer), size);
  jpeg_destroy_compress(&cinfo);
  std::free(buffer);
  return out;
}

}  // namespace plugslam::runtime
