#include "plugslam/png.h"

#include <png.h>

#include <vector>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

// libpng reports errors by longjmp: the message is kept here and thrown after the jump, from a
// frame that owns no C++ object created after setjmp.
void onError(png_structp png, png_const_charp message) {
  auto* text = static_cast<std::string*>(png_get_error_ptr(png));
  if (text) *text = message;
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

void append(png_structp png, png_bytep data, png_size_t size) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), size);
}
void flush(png_structp) {}

int colourType(int channels) {
  switch (channels) {
    case 1: return PNG_COLOR_TYPE_GRAY;
    case 2: return PNG_COLOR_TYPE_GRAY_ALPHA;
    case 3: return PNG_COLOR_TYPE_RGB;
    default: return PNG_COLOR_TYPE_RGB_ALPHA;
  }
}

// Everything libpng touches after setjmp lives in the caller's frame (rows, out, error).
bool encode(const PngPixels& p, const PngOptions& o, const std::vector<png_bytep>& rows,
            std::string& out, std::string& error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onError, onWarning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) {
    png_destroy_write_struct(&png, &info);
    error = "out of memory";
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &out, append, flush);
  png_set_compression_level(png, o.level);
  if (!o.filters) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  const size_t raw = (static_cast<size_t>(p.width) * p.channels * p.bit_depth / 8 + 1) * p.height;
  // One chunk: a buffer as large as the compressed data can get (zlib's deflateBound, roughly).
  png_set_compression_buffer_size(png, o.idat_bytes > 0 ? o.idat_bytes : raw + raw / 1000 + 64);
  png_set_IHDR(png, info, static_cast<png_uint_32>(p.width), static_cast<png_uint_32>(p.height),
               p.bit_depth, colourType(p.channels), PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (o.srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  if (p.bit_depth == 16) png_set_swap(png);  // PNG is big-endian, the samples are the host's
  png_write_rows(png, const_cast<png_bytepp>(rows.data()), static_cast<png_uint_32>(p.height));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

std::string encodePng(const PngPixels& p, const PngOptions& o) {
  if (p.width < 1 || p.height < 1 || !p.data)
    throw InputError("PNG: the image is empty (" + std::to_string(p.width) + " x " +
                     std::to_string(p.height) + " pixels)");
  if (p.channels < 1 || p.channels > 4)
    throw InputError("PNG: expected 1 to 4 channels, got " + std::to_string(p.channels));
  if (p.bit_depth != 8 && p.bit_depth != 16)
    throw InputError("PNG: expected 8 or 16 bits per sample, got " + std::to_string(p.bit_depth));
  if (o.level < 0 || o.level > 9)
    throw InputError("PNG: compression level " + std::to_string(o.level) + " is not in 0..9");
  const size_t row = static_cast<size_t>(p.width) * p.channels * (p.bit_depth / 8);
  const size_t stride = p.stride > 0 ? p.stride : row;
  if (stride < row)
    throw InputError("PNG: rows of " + std::to_string(row) + " bytes cannot be " +
                     std::to_string(stride) + " bytes apart");
  std::vector<png_bytep> rows(static_cast<size_t>(p.height));
  for (size_t y = 0; y < rows.size(); ++y) rows[y] = const_cast<png_bytep>(p.data + y * stride);
  std::string out, error;
  if (!encode(p, o, rows, out, error)) throw Error("PNG encoding failed: " + error);
  return out;
}

}  // namespace abi_v1
}  // namespace plugslam
