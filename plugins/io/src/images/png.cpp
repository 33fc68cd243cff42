#include "images/png.h"

#include <png.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {
namespace {

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<FILE, FileCloser>;

// libpng reports errors by longjmp; the message is kept here and turned into an exception
// after the jump, outside any frame that owns C++ objects created after setjmp.
void onError(png_structp png, png_const_charp message) {
  auto* text = static_cast<std::string*>(png_get_error_ptr(png));
  if (text) *text = message;
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

// rows: one pointer per row; bit_depth 8 or 16 (16-bit samples given in host order).
void writeRows(const std::string& path, int width, int height, int color_type, int bit_depth,
               const std::vector<const uint8_t*>& rows) {
  FilePtr file(std::fopen(path.c_str(), "wb"));
  if (!file) throw InputError("cannot write PNG '" + path + "'");
  std::string error;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    throw InputError("libpng: out of memory writing '" + path + "'");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw InputError("cannot write PNG '" + path + "': " + error);
  }
  png_init_io(png, file.get());
  png_set_compression_level(png, 1);  // fast: sequences have thousands of frames
  png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bit_depth == 16) png_set_swap(png);  // PNG is big-endian; our samples are little-endian
  png_write_rows(png, const_cast<png_bytepp>(rows.data()), static_cast<png_uint_32>(height));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  if (std::fflush(file.get()) != 0)
    throw InputError("cannot write PNG '" + path + "' (disk full?)");
}

}  // namespace

void writePng(const std::string& path, const Image& im) {
  if (im.channels != 1 && im.channels != 3)
    throw InputError("writePng: expected 1 or 3 channels, got " + std::to_string(im.channels));
  if (im.width < 1 || im.height < 1 ||
      im.data.size() < static_cast<size_t>(im.stride) * static_cast<size_t>(im.height))
    throw InputError("writePng: the image is empty or its data is shorter than stride * height");
  std::vector<const uint8_t*> rows(im.height);
  for (int y = 0; y < im.height; ++y) rows[y] = &im.data[static_cast<size_t>(y) * im.stride];
  writeRows(path, im.width, im.height, im.channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGB,
            8, rows);
}

void writePng16(const std::string& path, int width, int height,
                const std::vector<uint16_t>& values) {
  if (width < 1 || height < 1 ||
      values.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw InputError("writePng16: expected width * height values");
  std::vector<const uint8_t*> rows(height);
  for (int y = 0; y < height; ++y)
    rows[y] = reinterpret_cast<const uint8_t*>(&values[static_cast<size_t>(y) * width]);
  writeRows(path, width, height, PNG_COLOR_TYPE_GRAY, 16, rows);
}

PngImage readPng(const std::string& path) {
  FilePtr file(std::fopen(path.c_str(), "rb"));
  if (!file) throw InputError("cannot open PNG '" + path + "'");
  unsigned char sig[8] = {0};
  if (std::fread(sig, 1, 8, file.get()) != 8 || png_sig_cmp(sig, 0, 8) != 0)
    throw ParseError(path, 0, "not a PNG file (bad signature)");
  std::string error;
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &error, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw InputError("libpng: out of memory reading '" + path + "'");
  }
  PngImage out;
  std::vector<uint8_t> bytes;
  std::vector<png_bytep> rows;
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw ParseError(path, 0, "corrupt PNG: " + error);
  }
  png_init_io(png, file.get());
  png_set_sig_bytes(png, 8);
  png_read_info(png, info);
  const png_byte color = png_get_color_type(png, info);
  if (color == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (png_get_bit_depth(png, info) < 8) png_set_expand(png);
  if (png_get_bit_depth(png, info) == 16) png_set_swap(png);
  png_read_update_info(png, info);
  out.width = static_cast<int>(png_get_image_width(png, info));
  out.height = static_cast<int>(png_get_image_height(png, info));
  out.channels = png_get_channels(png, info);
  out.bit_depth = png_get_bit_depth(png, info);
  const size_t row_bytes = png_get_rowbytes(png, info);
  bytes.resize(row_bytes * static_cast<size_t>(out.height));
  rows.resize(out.height);
  for (int y = 0; y < out.height; ++y) rows[y] = &bytes[static_cast<size_t>(y) * row_bytes];
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  const size_t n = static_cast<size_t>(out.width) * out.height * out.channels;
  out.samples.resize(n);
  for (size_t i = 0; i < n; ++i) {
    if (out.bit_depth == 16) {
      out.samples[i] = static_cast<uint16_t>(bytes[2 * i] | (bytes[2 * i + 1] << 8));
    } else {
      out.samples[i] = bytes[i];
    }
  }
  return out;
}

std::vector<uint16_t> depthToUint16(const DepthImage& depth, double scale) {
  std::vector<uint16_t> out(depth.data.size(), 0);
  for (size_t i = 0; i < out.size(); ++i) {
    const double v = std::round(depth.data[i] * scale);
    out[i] = (v > 0.0 && v <= 65535.0) ? static_cast<uint16_t>(v) : 0;
  }
  return out;
}

}  // namespace io
}  // namespace plugslam
