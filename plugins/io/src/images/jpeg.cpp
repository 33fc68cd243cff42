#include "images/jpeg.h"

#include <jpeglib.h>

#include <csetjmp>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {
namespace {

// libjpeg reports errors by longjmp. The functions that call setjmp below take only pointers and
// create no C++ object that lives across a library call: what the decode fills lives in the
// caller's frame, so a jump skips no destructor and leaves no local indeterminate.
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

}  // namespace

bool isJpeg(const std::uint8_t* data, std::size_t size) {
  return size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
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
  checkImageSize(name, r.cinfo.image_width, r.cinfo.image_height);
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

}  // namespace io
}  // namespace plugslam
