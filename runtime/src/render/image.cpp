#include "render/image.h"

#include <cairo.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/png.h"

namespace plugslam::runtime::render {

namespace {

struct Bytes {
  const std::string* data;
  size_t offset = 0;
};

cairo_status_t readBytes(void* closure, unsigned char* out, unsigned int length) {
  auto* b = static_cast<Bytes*>(closure);
  if (b->data->size() - b->offset < length) return CAIRO_STATUS_READ_ERROR;
  std::memcpy(out, b->data->data() + b->offset, length);
  b->offset += length;
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

std::string encodePng(const RgbImage& image) {
  PngPixels pixels;
  pixels.data = image.samples.data();
  pixels.width = image.width;
  pixels.height = image.height;
  pixels.channels = 3;
  PngOptions picture;   // libpng's defaults: adaptive filters suit plots and map renderings
  picture.srgb = true;  // pictures for a screen
  return plugslam::encodePng(pixels, picture);
}

void writePng(const std::string& path, const RgbImage& image) {
  writeFileAtomically(path, encodePng(image));
}

RgbImage readPng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read '" + path + "'");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // Cairo's reader already expands grey and palettes, reduces 16 bits and premultiplies alpha
  // (which is composing on black): libpng stays behind Cairo and the SDK.
  Bytes source{&bytes};
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create_from_png_stream(readBytes, &source), cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw InputError("'" + path + "' is not a PNG: " +
                     cairo_status_to_string(cairo_surface_status(surface.get())));
  cairo_surface_flush(surface.get());
  const cairo_format_t format = cairo_image_surface_get_format(surface.get());
  if (format != CAIRO_FORMAT_RGB24 && format != CAIRO_FORMAT_ARGB32)
    throw InputError("'" + path + "': unexpected pixel format");
  RgbImage image;
  image.width = cairo_image_surface_get_width(surface.get());
  image.height = cairo_image_surface_get_height(surface.get());
  image.samples.resize(static_cast<size_t>(image.width) * image.height * 3);
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < image.height; ++y) {
    const auto* row = reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride);
    for (int x = 0; x < image.width; ++x) {
      const size_t i = (static_cast<size_t>(y) * image.width + x) * 3;
      image.samples[i] = static_cast<uint8_t>(row[x] >> 16);
      image.samples[i + 1] = static_cast<uint8_t>(row[x] >> 8);
      image.samples[i + 2] = static_cast<uint8_t>(row[x]);
    }
  }
  return image;
}

}  // namespace plugslam::runtime::render
