#include "plugslam/sensor_data.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string>

#include "plugslam/archive.h"
#include "properties/base64.h"

namespace plugslam {
inline namespace abi_v1 {
namespace {

constexpr int kMaxSide = 1 << 16;

void checkSize(InArchive& ar, int width, int height) {
  if (width < 0 || height < 0 || width > kMaxSide || height > kMaxSide)
    ar.fail("image size must be within 0.." + std::to_string(kMaxSide) + " pixels per side");
}

// One field list per type serves both directions: OutArchive::field reads the member,
// InArchive::field fills it.
template <class Ar, class S>
void scanFields(Ar& ar, S& s) {
  ar.beginObject();
  ar.field("stamp", s.stamp);
  ar.field("angle_min", s.angle_min);
  ar.field("angle_increment", s.angle_increment);
  ar.field("range_min", s.range_min);
  ar.field("range_max", s.range_max);
  ar.field("ranges", s.ranges);
  ar.field("mount", s.mount);
  ar.endObject();
}

template <class Ar, class O>
void odometryFields(Ar& ar, O& o) {
  ar.beginObject();
  ar.field("stamp", o.stamp);
  ar.field("pose", o.pose);
  ar.endObject();
}

// Width and height in pixels, as every type with a size writes them.
template <class Ar, class T>
void sizeFields(Ar& ar, T& t) {
  ar.field("width", t.width);
  ar.field("height", t.height);
}

// The pinhole fields, CameraInfo's first as CameraIntrinsics', for save and load.
template <class Ar, class C>
void pinholeFields(Ar& ar, C& c) {
  ar.field("fx", c.fx);
  ar.field("fy", c.fy);
  ar.field("cx", c.cx);
  ar.field("cy", c.cy);
  sizeFields(ar, c);
}

// The pinhole fields as saved, and as loaded with their checks.
void pinhole(OutArchive& ar, const CameraPinhole& c) { pinholeFields(ar, c); }
void pinhole(InArchive& ar, CameraPinhole& c) {
  pinholeFields(ar, c);
  if (!std::isfinite(c.fx) || !std::isfinite(c.fy)) ar.fail("camera focal lengths must be finite");
  checkSize(ar, c.width, c.height);
}

template <class Ar, class C>
void intrinsicsFields(Ar& ar, C& c) {
  ar.beginObject();
  pinhole(ar, c);
  ar.field("distortion", c.distortion);
  ar.endObject();
}

// The fields before a depth image's pixels, shared by save and load.
template <class Ar, class D>
void depthHeader(Ar& ar, D& d) {
  ar.field("stamp", d.stamp);
  sizeFields(ar, d);
}

// An image's: the depth image's, then its pixel layout.
template <class Ar, class I>
void imageHeader(Ar& ar, I& im) {
  depthHeader(ar, im);
  ar.field("channels", im.channels);
  ar.field("stride", im.stride);
}

}  // namespace

void save(OutArchive& ar, const LaserScan& s) { scanFields(ar, s); }
void load(InArchive& ar, LaserScan& s) { scanFields(ar, s); }
void save(OutArchive& ar, const Odometry2D& o) { odometryFields(ar, o); }
void load(InArchive& ar, Odometry2D& o) { odometryFields(ar, o); }

bool Distortion::valid() const {
  const size_t n = coefficients.size();
  switch (model) {
    case Model::kNone:
      return n == 0;
    case Model::kRadialTangential:
      return n == 4 || n == 5 || n == 8 || n == 12 || n == 14;
    case Model::kEquidistant:
      return n == 4;
  }
  return false;
}

bool Distortion::isIdentity() const {
  return model == Model::kNone ||
         std::all_of(coefficients.begin(), coefficients.end(), [](double c) { return c == 0.0; });
}

bool parseDistortionModel(const std::string& name, Distortion::Model& model) {
  std::string n = name;
  for (char& ch : n) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (n.empty() || n == "none") {
    model = Distortion::Model::kNone;
  } else if (n == "radial-tangential" || n == "radtan" || n == "plumb_bob" ||
             n == "rational_polynomial") {
    model = Distortion::Model::kRadialTangential;
  } else if (n == "equidistant" || n == "fisheye") {
    model = Distortion::Model::kEquidistant;
  } else {
    return false;
  }
  return true;
}

const char* distortionModelName(Distortion::Model model) {
  switch (model) {
    case Distortion::Model::kNone:
      return "none";
    case Distortion::Model::kRadialTangential:
      return "radial-tangential";
    case Distortion::Model::kEquidistant:
      return "equidistant";
  }
  return "none";
}

void save(OutArchive& ar, const Distortion& d) {
  ar.beginObject();
  ar.field("model", std::string(distortionModelName(d.model)));
  ar.field("coefficients", d.coefficients);
  ar.endObject();
}

void load(InArchive& ar, Distortion& d) {
  ar.beginObject();
  std::string name;
  ar.field("model", name);
  if (!parseDistortionModel(name, d.model))
    ar.fail("unknown distortion model '" + name +
            "' (expected none, radial-tangential or equidistant)");
  ar.field("coefficients", d.coefficients);
  if (!d.valid())
    ar.fail(std::to_string(d.coefficients.size()) + " coefficients do not fit the " +
            distortionModelName(d.model) + " model (none: 0, radial-tangential: 4, 5, 8, 12 or " +
            "14, equidistant: 4)");
  ar.endObject();
}

void save(OutArchive& ar, const CameraIntrinsics& c) { intrinsicsFields(ar, c); }
void load(InArchive& ar, CameraIntrinsics& c) { intrinsicsFields(ar, c); }

void save(OutArchive& ar, const CameraInfo& c) {
  ar.beginObject();
  pinhole(ar, c);
  ar.field("baseline", c.baseline);
  ar.field("mount", c.mount);
  ar.field("distortion", c.distortion);
  if (c.second) {
    ar.field("second", *c.second);
    ar.field("second_pose", c.second_pose);
  }
  ar.endObject();
}

void load(InArchive& ar, CameraInfo& c) {
  ar.beginObject();
  pinhole(ar, c);
  ar.field("baseline", c.baseline);
  ar.field("mount", c.mount);
  // Archives written before ABI 1.5 have neither: undistorted, and no second camera.
  c.distortion = Distortion{};
  if (ar.hasKey("distortion")) ar.field("distortion", c.distortion);
  c.second.reset();
  c.second_pose = Eigen::Isometry3d::Identity();
  if (ar.hasKey("second")) {
    c.second.emplace();
    ar.field("second", *c.second);
    ar.field("second_pose", c.second_pose);
  }
  ar.endObject();
}

void save(OutArchive& ar, const Image& im) {
  ar.beginObject();
  imageHeader(ar, im);
  ar.field("data", detail::toBase64(im.data.data(), im.data.size()));
  ar.endObject();
}

void load(InArchive& ar, Image& im) {
  ar.beginObject();
  imageHeader(ar, im);
  checkSize(ar, im.width, im.height);
  if (im.channels < 1 || im.channels > 4) ar.fail("image channels must be 1..4");
  if (im.stride < im.width * im.channels) ar.fail("image stride must be >= width * channels");
  std::string text;
  ar.field("data", text);
  if (!detail::fromBase64(text, im.data)) ar.fail("image data is not valid base64");
  if (im.data.size() != static_cast<size_t>(im.stride) * static_cast<size_t>(im.height))
    ar.fail("image data holds " + std::to_string(im.data.size()) +
            " bytes, expected stride * height = " +
            std::to_string(static_cast<size_t>(im.stride) * static_cast<size_t>(im.height)));
  ar.endObject();
}

void save(OutArchive& ar, const DepthImage& d) {
  ar.beginObject();
  depthHeader(ar, d);
  std::vector<uint8_t> bytes(d.data.size() * 4);
  for (size_t i = 0; i < d.data.size(); ++i) {
    uint32_t bits;
    std::memcpy(&bits, &d.data[i], 4);
    for (int k = 0; k < 4; ++k) bytes[4 * i + k] = static_cast<uint8_t>(bits >> (8 * k));
  }
  ar.field("data", detail::toBase64(bytes.data(), bytes.size()));
  ar.endObject();
}

void load(InArchive& ar, DepthImage& d) {
  ar.beginObject();
  depthHeader(ar, d);
  checkSize(ar, d.width, d.height);
  std::string text;
  ar.field("data", text);
  std::vector<uint8_t> bytes;
  if (!detail::fromBase64(text, bytes)) ar.fail("depth data is not valid base64");
  const size_t n = static_cast<size_t>(d.width) * static_cast<size_t>(d.height);
  if (bytes.size() != 4 * n)
    ar.fail("depth data holds " + std::to_string(bytes.size()) +
            " bytes, expected 4 * width * height = " + std::to_string(4 * n));
  d.data.resize(n);
  for (size_t i = 0; i < n; ++i) {
    uint32_t bits = 0;
    for (int k = 0; k < 4; ++k) bits |= uint32_t(bytes[4 * i + k]) << (8 * k);
    std::memcpy(&d.data[i], &bits, 4);
  }
  ar.endObject();
}

}  // namespace abi_v1
}  // namespace plugslam
