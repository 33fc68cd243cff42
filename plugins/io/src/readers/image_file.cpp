#include "readers/image_file.h"

#include <jpeglib.h>
#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {
namespace {

bool isPng(const std::uint8_t* data, std::size_t size) {
  return size >= 8 && png_sig_cmp(data, 0, 8) == 0;
}
bool isJpeg(const std::uint8_t* data, std::size_t size) {
  return size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
}

void checkPixels(const std::string& name, std::size_t width, std::size_t height) {
  if (width == 0 || height == 0)
    throw ParseError(name, 0, "image has no pixels (" + std::to_string(width) + "x" +
                                  std::to_string(height) + ")");
  if (width > kMaxImagePixels / height)
    throw ParseError(name, 0, "image of " + std::to_string(width) + "x" + std::to_string(height) +
                                  " pixels is larger than the " +
                                  std::to_string(kMaxImagePixels) + " pixels accepted");
}

// ---- PNG -------------------------------------------------------------------------------------
// libpng and libjpeg report errors by longjmp. Each function that calls setjmp below takes only
// pointers and creates no C++ object that lives across a library call: what the decode fills
// lives in the caller's frame, so a jump skips no destructor and leaves no local indeterminate.

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

void pngError(png_structp png, png_const_charp message) {
  auto* read = static_cast<PngRead*>(png_get_error_ptr(png));
  read->error = message;
  png_longjmp(png, 1);
}
// Ancillary-chunk problems (a bad sRGB profile, a CRC error in text chunks) do not touch pixels.
void pngWarning(png_structp, png_const_charp) {}

void pngReadBytes(png_structp png, png_bytep out, png_size_t n) {
  auto* read = static_cast<PngRead*>(png_get_io_ptr(png));
  if (n > read->size - read->pos) png_error(png, "file is truncated");
  std::memcpy(out, read->data + read->pos, n);
  read->pos += n;
}

// Reads the header into r; false (r->error set) when libpng failed.
bool pngReadHeader(PngRead* r) {
  r->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, r, pngError, pngWarning);
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
  checkPixels(name, r.width, r.height);
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

// ---- JPEG ------------------------------------------------------------------------------------

struct JpegRead {
  jpeg_decompress_struct cinfo;
  jpeg_error_mgr err;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {0};
  bool created = false;
  ~JpegRead() {
    if (created) jpeg_destroy_decompress(&cinfo);
  }
};

void jpegErrorExit(j_common_ptr cinfo) {
  auto* r = static_cast<JpegRead*>(cinfo->client_data);
  (*cinfo->err->format_message)(cinfo, r->message);
  std::longjmp(r->jump, 1);
}

// A warning (level -1) is corrupt data that libjpeg would paper over, e.g. "Premature end of
// JPEG file" on a truncated file, which it fills with grey: for SLAM that is an error too.
void jpegEmitMessage(j_common_ptr cinfo, int level) {
  if (level < 0) jpegErrorExit(cinfo);
}

// Reads the header and starts decompression into the colour space asked for; false on error.
bool jpegStart(JpegRead* r, const std::uint8_t* data, std::size_t size, bool grey) {
  if (setjmp(r->jump)) return false;
  jpeg_create_decompress(&r->cinfo);
  r->created = true;
  jpeg_mem_src(&r->cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&r->cinfo, TRUE);
  if (grey || r->cinfo.num_components < 3) {
    // Grey wanted, or a grey file asked for as stored (RGB from grey is done after decoding).
    r->cinfo.out_color_space = JCS_GRAYSCALE;
  } else {
    r->cinfo.out_color_space = JCS_RGB;
  }
  return true;
}

bool jpegFinish(JpegRead* r, std::uint8_t* pixels, std::size_t stride) {
  if (setjmp(r->jump)) return false;
  jpeg_start_decompress(&r->cinfo);
  while (r->cinfo.output_scanline < r->cinfo.output_height) {
    JSAMPROW row = pixels + static_cast<std::size_t>(r->cinfo.output_scanline) * stride;
    jpeg_read_scanlines(&r->cinfo, &row, 1);
  }
  jpeg_finish_decompress(&r->cinfo);
  return true;
}

Image decodeJpeg(const std::uint8_t* data, std::size_t size, const std::string& name,
                 ImageChannels channels) {
  JpegRead r;
  r.cinfo.err = jpeg_std_error(&r.err);
  r.err.error_exit = jpegErrorExit;
  r.err.emit_message = jpegEmitMessage;
  r.cinfo.client_data = &r;
  if (!jpegStart(&r, data, size, channels == ImageChannels::kGrey))
    throw ParseError(name, 0, std::string("corrupt JPEG: ") + r.message);
  checkPixels(name, r.cinfo.image_width, r.cinfo.image_height);
  const int c = r.cinfo.out_color_space == JCS_GRAYSCALE ? 1 : 3;
  Image image;
  image.resize(static_cast<int>(r.cinfo.image_width), static_cast<int>(r.cinfo.image_height), c);
  if (!jpegFinish(&r, image.data.data(), static_cast<std::size_t>(image.stride)))
    throw ParseError(name, 0, std::string("corrupt JPEG: ") + r.message);
  if (r.cinfo.output_width != r.cinfo.image_width || r.cinfo.output_height != r.cinfo.image_height)
    throw ParseError(name, 0, "JPEG decoded to another size than its header states");
  if (channels == ImageChannels::kRgb && c == 1) {
    Image rgb;
    rgb.resize(image.width, image.height, 3);
    for (std::size_t i = 0; i < image.data.size(); ++i)
      rgb.data[3 * i] = rgb.data[3 * i + 1] = rgb.data[3 * i + 2] = image.data[i];
    return rgb;
  }
  return image;
}

}  // namespace

Image decodeImage(const std::uint8_t* data, std::size_t size, const std::string& name,
                  ImageChannels channels) {
  if (isPng(data, size)) return decodePng(data, size, name, channels);
  if (isJpeg(data, size)) return decodeJpeg(data, size, name, channels);
  throw ParseError(name, 0,
                   size == 0 ? std::string("empty file, expected a PNG or JPEG image")
                             : std::string("not a PNG or JPEG image (unknown signature)"));
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
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::uint16_t v = values[i];
    depth.data[i] = (v == 0 || v == 65535) ? 0.0f : static_cast<float>(v) * scale;
  }
  return depth;
}

std::vector<std::uint8_t> readFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open '" + path + "'");
  in.seekg(0, std::ios::end);
  const std::streamoff n = in.tellg();
  if (n < 0) throw InputError("cannot read '" + path + "' (not a regular file?)");
  in.seekg(0, std::ios::beg);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(n));
  if (n > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), n))
    throw InputError("cannot read '" + path + "'");
  return bytes;
}

Image readImageFile(const std::string& path, ImageChannels channels) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return decodeImage(bytes.data(), bytes.size(), path, channels);
}

DepthImage readDepthFile(const std::string& path, double units_per_metre) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return decodeDepthPng(bytes.data(), bytes.size(), path, units_per_metre);
}

}  // namespace io
}  // namespace plugslam
