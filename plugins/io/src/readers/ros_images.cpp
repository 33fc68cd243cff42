#include "readers/ros_images.h"

#include <cmath>
#include <cstring>

#include "images/image_file.h"
#include "images/png.h"
#include "plugslam/errors.h"

namespace plugslam {
namespace io {

namespace {

[[noreturn]] void fail(const std::string& why) { throw ParseError("image message", 0, why); }

std::string sizeText(std::uint32_t w, std::uint32_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// The data must hold `height` rows of `step` bytes, each with `width` pixels of `bytes` bytes.
void checkLayout(const ImageMsg& m, std::size_t bytes) {
  checkImageSize("image message", m.width, m.height);
  if (std::size_t{m.step} < std::size_t{m.width} * bytes)
    fail("step " + std::to_string(m.step) + " is shorter than a row of " +
         std::to_string(m.width) + " " + m.encoding + " pixels (" +
         std::to_string(std::size_t{m.width} * bytes) + " bytes)");
  if (m.data.size() != std::size_t{m.step} * m.height)
    fail("data is " + std::to_string(m.data.size()) + " bytes, a " + sizeText(m.width, m.height) +
         " " + m.encoding + " image of step " + std::to_string(m.step) + " is " +
         std::to_string(std::size_t{m.step} * m.height));
}

bool isDepthEncoding(const std::string& e) { return e == "16UC1" || e == "32FC1"; }

}  // namespace

Image imageFromRos(const ImageMsg& m) {
  // Per encoding: bytes per pixel, output channels, where R, G, B (or grey) sit in the pixel.
  struct Layout {
    std::size_t bytes;
    int channels;
    int r, g, b;
  };
  Layout l{};
  const std::string& e = m.encoding;
  if (e == "mono8" || e == "8UC1") l = {1, 1, 0, 0, 0};
  else if (e == "mono16") l = {2, 1, 0, 0, 0};
  else if (e == "rgb8") l = {3, 3, 0, 1, 2};
  else if (e == "bgr8" || e == "8UC3") l = {3, 3, 2, 1, 0};
  else if (e == "rgba8") l = {4, 3, 0, 1, 2};
  else if (e == "bgra8" || e == "8UC4") l = {4, 3, 2, 1, 0};
  else if (isDepthEncoding(e))
    fail("encoding " + e + " is a depth image: map its topic as `depth`, not `images`");
  else
    fail("encoding '" + e + "' is not read (mono8, mono16, rgb8, bgr8, rgba8, bgra8)");
  checkLayout(m, l.bytes);
  Image im;
  im.resize(static_cast<int>(m.width), static_cast<int>(m.height), l.channels);
  for (std::uint32_t y = 0; y < m.height; ++y) {
    const std::uint8_t* row = m.data.data() + std::size_t{y} * m.step;
    std::uint8_t* out = im.data.data() + std::size_t{y} * static_cast<std::size_t>(im.stride);
    for (std::uint32_t x = 0; x < m.width; ++x) {
      const std::uint8_t* px = row + x * l.bytes;
      if (l.bytes == 2) {
        out[x] = m.is_bigendian ? px[0] : px[1];  // the high byte
      } else if (l.channels == 1) {
        out[x] = px[0];
      } else {
        out[3 * x] = px[l.r];
        out[3 * x + 1] = px[l.g];
        out[3 * x + 2] = px[l.b];
      }
    }
  }
  return im;
}

Image imageFromRos(const CompressedImageMsg& m) {
  if (m.format.find("compressedDepth") != std::string::npos)
    fail("format '" + m.format + "' (compressedDepth) is not read: record the raw depth topic");
  return decodeImage(m.data.data(), m.data.size(), "compressed image (" + m.format + ")");
}

DepthImage depthFromRos(const ImageMsg& m) {
  const bool mm = m.encoding == "16UC1" || m.encoding == "mono16";
  if (!mm && m.encoding != "32FC1")
    fail("depth encoding '" + m.encoding + "' is not read (16UC1 in mm, 32FC1 in m)");
  checkLayout(m, mm ? 2 : 4);
  DepthImage d;
  d.resize(static_cast<int>(m.width), static_cast<int>(m.height));
  // The depth PNGs' conversion, so a bag and a folder of the same millimetres give the same floats.
  const float scale = static_cast<float>(1.0 / 1000.0);
  for (std::uint32_t y = 0; y < m.height; ++y) {
    const std::uint8_t* row = m.data.data() + std::size_t{y} * m.step;
    float* out = d.data.data() + std::size_t{y} * m.width;
    for (std::uint32_t x = 0; x < m.width; ++x) {
      if (mm) {
        const std::uint8_t* p = row + 2 * x;
        const std::uint16_t v = m.is_bigendian ? static_cast<std::uint16_t>(p[0] << 8 | p[1])
                                               : static_cast<std::uint16_t>(p[1] << 8 | p[0]);
        out[x] = depthFromUnits(v, scale);
      } else {
        std::uint8_t b[4];
        std::memcpy(b, row + 4 * x, 4);
        if (m.is_bigendian) {
          std::swap(b[0], b[3]);
          std::swap(b[1], b[2]);
        }
        float v;
        std::memcpy(&v, b, 4);
        out[x] = std::isfinite(v) && v > 0.0f ? v : 0.0f;
      }
    }
  }
  return d;
}

bool isRectifiedCamera(const CameraInfoMsg& m) {
  for (double v : m.d)
    if (v != 0.0) return false;
  static const std::array<double, 9> identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  if (m.r != identity) return false;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col)
      if (m.k[3 * row + col] != m.p[4 * row + col]) return false;
  return true;
}

CameraIntrinsics intrinsicsFromRos(const CameraInfoMsg& m, bool rectified) {
  CameraIntrinsics c;
  c.width = static_cast<int>(m.width);
  c.height = static_cast<int>(m.height);
  if (rectified) {
    c.fx = m.p[0];
    c.fy = m.p[5];
    c.cx = m.p[2];
    c.cy = m.p[6];
  } else {
    c.fx = m.k[0];
    c.fy = m.k[4];
    c.cx = m.k[2];
    c.cy = m.k[5];
    bool zero = true;
    for (double v : m.d) zero = zero && v == 0.0;
    if (!zero) {
      if (!parseDistortionModel(m.distortion_model, c.distortion.model))
        throw ParseError("camera info", 0,
                         "distortion model '" + m.distortion_model +
                             "' is not read (plumb_bob, rational_polynomial, equidistant)");
      c.distortion.coefficients = m.d;
      if (!c.distortion.valid())
        throw ParseError("camera info", 0,
                         std::to_string(m.d.size()) + " distortion coefficients do not fit " +
                             "model '" + m.distortion_model + "'");
    }
  }
  if (!(c.fx > 0) || !(c.fy > 0))
    throw ParseError("camera info", 0,
                     std::string(rectified ? "P" : "K") + " has focal lengths " +
                         std::to_string(c.fx) + ", " + std::to_string(c.fy) +
                         " (expected positive; an uncalibrated camera?)");
  return c;
}

}  // namespace io
}  // namespace plugslam
