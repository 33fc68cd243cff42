#include "images/png.h"

#include <png.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <string>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/png.h"

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
// Ancillary-chunk problems (a bad sRGB profile, a CRC error in text chunks) are warnings that do
// not touch pixels.
void onError(png_structp png, png_const_charp message) {
  auto* text = static_cast<std::string*>(png_get_error_ptr(png));
  if (text) *text = message;
  png_longjmp(png, 1);
}
void onWarning(png_structp, png_const_charp) {}

// Image sequences have thousands of frames: zlib level 1 (fast), libpng's row filters. Encoded in
// memory, then written atomically: a crash mid-sequence leaves no truncated image.
void writeEncoded(const std::string& path, const PngPixels& pixels) {
  PngOptions fast;
  fast.level = 1;
  writeFileAtomically(path, encodePng(pixels, fast));
}

// Reading: each function that calls setjmp below takes only pointers and creates no C++ object
// that lives across a library call; what the decode fills lives in the caller's frame, so a jump
// skips no destructor and leaves no local indeterminate.

struct PngRead {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  std::string error;
  png_structp png = nullptr;
  png_infop info = nullptr;
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
  std::vector<png_bytep> rows;
  ~PngRead() { png_destroy_read_struct(&png, &info, nullptr); }
};

void pngReadBytes(png_structp png, png_bytep out, png_size_t n) {
  auto* read = static_cast<PngRead*>(png_get_io_ptr(png));
  if (n > read->size - read->pos) png_error(png, "file is truncated");
  std::memcpy(out, read->data + read->pos, n);
  read->pos += n;
}

// Reads the header into r; false (r->error set) when libpng failed.
bool pngReadHeader(PngRead* r) {
  r->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r->error, onError, onWarning);
  if (r->png) r->info = png_create_info_struct(r->png);
  if (!r->png || !r->info) return false;
  if (setjmp(png_jmpbuf(r->png))) return false;
  png_set_read_fn(r->png, r, pngReadBytes);
  png_set_user_limits(r->png, 1u << 16, 1u << 16);
  png_read_info(r->png, r->info);
  r->width = png_get_image_width(r->png, r->info);
  r->height = png_get_image_height(r->png, r->info);
  r->bit_depth = png_get_bit_depth(r->png, r->info);
  r->color_type = png_get_color_type(r->png, r->info);
  return true;
}

// Applies the transforms chosen and reads the pixels into r->rows, each of row_bytes; false when
// libpng failed or the transformed rows are not row_bytes long.
bool pngReadRows(PngRead* r, std::size_t row_bytes) {
  if (setjmp(png_jmpbuf(r->png))) return false;
  png_read_update_info(r->png, r->info);
  if (png_get_rowbytes(r->png, r->info) != row_bytes) {
    r->error = "unexpected row size after the transforms";
    return false;
  }
  png_read_image(r->png, r->rows.data());
  png_read_end(r->png, nullptr);
  return true;
}

std::string pngKind(const PngRead& r) {
  const char* colour = r.color_type == PNG_COLOR_TYPE_GRAY         ? "grey"
                       : r.color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? "grey+alpha"
                       : r.color_type == PNG_COLOR_TYPE_RGB        ? "RGB"
                       : r.color_type == PNG_COLOR_TYPE_RGB_ALPHA  ? "RGBA"
                                                                   : "palette";
  return std::to_string(r.bit_depth) + "-bit " + colour;
}

void openPng(PngRead& r, const std::uint8_t* data, std::size_t size, const std::string& name) {
  r.data = data;
  r.size = size;
  if (!pngReadHeader(&r))
    throw ParseError(name, 0, "corrupt PNG: " + (r.error.empty() ? "out of memory" : r.error));
  checkImageSize(name, r.width, r.height);
}

}  // namespace

void writePng(const std::string& path, const Image& im) {
  if (im.channels != 1 && im.channels != 3)
    throw InputError("writePng: expected 1 or 3 channels, got " + std::to_string(im.channels));
  if (im.width < 1 || im.height < 1 ||
      im.data.size() < static_cast<size_t>(im.stride) * static_cast<size_t>(im.height))
    throw InputError("writePng: the image is empty or its data is shorter than stride * height");
  PngPixels pixels;
  pixels.data = im.data.data();
  pixels.width = im.width;
  pixels.height = im.height;
  pixels.channels = im.channels;
  pixels.stride = static_cast<size_t>(im.stride);
  writeEncoded(path, pixels);
}

void writePng16(const std::string& path, int width, int height,
                const std::vector<uint16_t>& values) {
  if (width < 1 || height < 1 ||
      values.size() != static_cast<size_t>(width) * static_cast<size_t>(height))
    throw InputError("writePng16: expected width * height values");
  PngPixels pixels;
  pixels.data = reinterpret_cast<const uint8_t*>(values.data());
  pixels.width = width;
  pixels.height = height;
  pixels.bit_depth = 16;
  writeEncoded(path, pixels);
}

PngImage readPng(const std::string& path) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  if (!isPng(bytes.data(), bytes.size()))
    throw ParseError(path, 0, "not a PNG file (bad signature)");
  PngRead r;
  openPng(r, bytes.data(), bytes.size(), path);
  if (r.color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
  if (r.bit_depth < 8) png_set_expand(r.png);
  if (r.bit_depth == 16) png_set_swap(r.png);
  PngImage out;
  out.width = static_cast<int>(r.width);
  out.height = static_cast<int>(r.height);
  out.bit_depth = r.bit_depth == 16 ? 16 : 8;
  out.channels = (r.color_type & PNG_COLOR_MASK_COLOR) || r.color_type == PNG_COLOR_TYPE_PALETTE
                     ? 3
                     : 1;
  if (r.color_type & PNG_COLOR_MASK_ALPHA) ++out.channels;
  const std::size_t row_bytes =
      static_cast<std::size_t>(out.width) * out.channels * (out.bit_depth / 8);
  std::vector<std::uint8_t> pixels(row_bytes * r.height);
  r.rows.resize(r.height);
  for (png_uint_32 y = 0; y < r.height; ++y) r.rows[y] = pixels.data() + y * row_bytes;
  if (!pngReadRows(&r, row_bytes)) throw ParseError(path, 0, "corrupt PNG: " + r.error);
  const std::size_t n = static_cast<std::size_t>(out.width) * out.height * out.channels;
  out.samples.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    out.samples[i] = out.bit_depth == 16
                         ? static_cast<uint16_t>(pixels[2 * i] | (pixels[2 * i + 1] << 8))
                         : pixels[i];
  return out;
}

bool isPng(const std::uint8_t* data, std::size_t size) {
  return size >= 8 && png_sig_cmp(data, 0, 8) == 0;
}

Image decodePng(const std::uint8_t* data, std::size_t size, const std::string& name,
                ImageChannels channels) {
  PngRead r;
  openPng(r, data, size, name);
  if (r.color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(r.png);
  if (r.color_type == PNG_COLOR_TYPE_GRAY && r.bit_depth < 8) png_set_expand_gray_1_2_4_to_8(r.png);
  if (r.bit_depth == 16) png_set_strip_16(r.png);
  if (r.color_type & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(r.png);
  const bool colour = (r.color_type & PNG_COLOR_MASK_COLOR) != 0;
  int out_channels = colour ? 3 : 1;
  if (channels == ImageChannels::kGrey && colour) {
    // BT.601 luma, as JPEG's Y and OpenCV's cvtColor, in 1e-5 units.
    png_set_rgb_to_gray_fixed(r.png, 1, 29900, 58700);
    out_channels = 1;
  } else if (channels == ImageChannels::kRgb && !colour) {
    png_set_gray_to_rgb(r.png);
    out_channels = 3;
  }
  Image image;
  image.resize(static_cast<int>(r.width), static_cast<int>(r.height), out_channels);
  r.rows.resize(r.height);
  for (png_uint_32 y = 0; y < r.height; ++y)
    r.rows[y] = image.data.data() + static_cast<std::size_t>(y) * image.stride;
  if (!pngReadRows(&r, static_cast<std::size_t>(image.stride)))
    throw ParseError(name, 0, "corrupt PNG: " + r.error);
  return image;
}

DepthImage decodeDepthPng(const std::uint8_t* data, std::size_t size, const std::string& name,
                          double units_per_metre) {
  if (!isPng(data, size))
    throw ParseError(name, 0,
                     size == 0 ? "empty file, expected a 16-bit PNG depth image"
                               : "not a PNG file (bad signature): depth is read from 16-bit PNGs");
  PngRead r;
  openPng(r, data, size, name);
  if (r.color_type != PNG_COLOR_TYPE_GRAY || r.bit_depth != 16)
    throw ParseError(name, 0, "depth image is " + pngKind(r) + ", expected a 16-bit grey PNG");
  std::vector<std::uint16_t> values(static_cast<std::size_t>(r.width) * r.height);
  // PNG stores big-endian samples.
  const std::uint16_t probe = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &probe, 1);
  if (first == 1) png_set_swap(r.png);
  r.rows.resize(r.height);
  for (png_uint_32 y = 0; y < r.height; ++y)
    r.rows[y] = reinterpret_cast<png_bytep>(values.data() + static_cast<std::size_t>(y) * r.width);
  if (!pngReadRows(&r, static_cast<std::size_t>(r.width) * 2))
    throw ParseError(name, 0, "corrupt PNG: " + r.error);
  DepthImage depth;
  depth.resize(static_cast<int>(r.width), static_cast<int>(r.height));
  const float scale = static_cast<float>(1.0 / units_per_metre);
  for (std::size_t i = 0; i < values.size(); ++i) depth.data[i] = depthFromUnits(values[i], scale);
  return depth;
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
