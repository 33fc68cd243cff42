#include "plugslam/landmarks/feature_set.h"

#include <algorithm>
#include <string>

#include "plugslam/archive.h"
#include "plugslam/errors.h"
#include "properties/base64.h"

namespace plugslam {
inline namespace abi_v1 {

Eigen::Matrix3d pointCovariance(const PinholeCamera& camera, const Eigen::Vector2d& uv, double q,
                                double sigma_px, double sigma_q) {
  // p = ((u - cx) / (fx q), (v - cy) / (fy q), 1 / q): Jacobian w.r.t. (u, v, q).
  const double xn = (uv.x() - camera.cx) / camera.fx, yn = (uv.y() - camera.cy) / camera.fy;
  const double z = 1.0 / q;
  Eigen::Matrix3d j;
  j << z / camera.fx, 0, -xn * z * z,  //
      0, z / camera.fy, -yn * z * z,   //
      0, 0, -z * z;
  const Eigen::Vector3d var(sigma_px * sigma_px, sigma_px * sigma_px, sigma_q * sigma_q);
  return j * var.asDiagonal() * j.transpose();
}

void FeatureSet::clear() {
  pixels.clear();
  pixel_sigma.clear();
  scales.clear();
  inverse_depth.clear();
  inverse_depth_sigma.clear();
  points.clear();
  covariances.clear();
  descriptors.clear();
  colours.clear();
}

void FeatureSet::reserve(size_t n) {
  pixels.reserve(n);
  pixel_sigma.reserve(n);
  scales.reserve(n);
  inverse_depth.reserve(n);
  inverse_depth_sigma.reserve(n);
  points.reserve(n);
  covariances.reserve(n);
  descriptors.reserve(n * static_cast<size_t>(descriptor_bytes));
  colours.reserve(n);
}

namespace {
// Appends one keypoint with inverse depth q (0: none) and its noise.
void pushKeypoint(FeatureSet& f, const Eigen::Vector2d& uv, double sigma_px, double q,
                  double sigma_q, const uint8_t* descriptor, uint32_t colour, double scale) {
  f.pixels.push_back(uv);
  f.pixel_sigma.push_back(sigma_px);
  f.scales.push_back(scale);
  if (q > 0) {
    const double z = 1.0 / q;
    f.inverse_depth.push_back(q);
    f.inverse_depth_sigma.push_back(sigma_q);
    f.points.emplace_back((uv.x() - f.camera.cx) / f.camera.fx * z,
                          (uv.y() - f.camera.cy) / f.camera.fy * z, z);
    f.covariances.push_back(pointCovariance(f.camera, uv, q, sigma_px, sigma_q));
  } else {
    f.inverse_depth.push_back(0.0);
    f.inverse_depth_sigma.push_back(0.0);
    f.points.emplace_back(Eigen::Vector3d::Zero());
    f.covariances.emplace_back(Eigen::Matrix3d::Zero());
  }
  f.descriptors.insert(f.descriptors.end(), descriptor, descriptor + f.descriptor_bytes);
  f.colours.push_back(colour);
}
}  // namespace

void FeatureSet::pushDepth(const Eigen::Vector2d& uv, double sigma_px, double z, double sigma_z,
                           const uint8_t* descriptor, uint32_t colour, double scale) {
  // sigma of 1/z to first order: sigma_z / z^2.
  if (z > 0)
    pushKeypoint(*this, uv, sigma_px, 1.0 / z, sigma_z / (z * z), descriptor, colour, scale);
  else
    pushKeypoint(*this, uv, sigma_px, 0.0, 0.0, descriptor, colour, scale);
}

void FeatureSet::pushStereo(const Eigen::Vector2d& uv, double sigma_px, double disparity,
                            double sigma_d, const uint8_t* descriptor, uint32_t colour,
                            double scale) {
  if (!(camera.baseline > 0))
    throw InputError("FeatureSet::pushStereo: the camera has no stereo baseline");
  // z = fx b / d, so 1/z = d / (fx b): inverse depth is disparity in other units.
  const double fb = camera.fx * camera.baseline;
  if (disparity > 0)
    pushKeypoint(*this, uv, sigma_px, disparity / fb, sigma_d / fb, descriptor, colour, scale);
  else
    pushKeypoint(*this, uv, sigma_px, 0.0, 0.0, descriptor, colour, scale);
}

void FeatureSet::checkConsistent() const {
  const size_t n = size();
  if (pixel_sigma.size() != n || scales.size() != n || inverse_depth.size() != n || inverse_depth_sigma.size() != n ||
      points.size() != n || covariances.size() != n || colours.size() != n ||
      descriptor_bytes <= 0 || descriptors.size() != n * static_cast<size_t>(descriptor_bytes))
    throw InputError("FeatureSet: expected every array to hold " + std::to_string(n) +
                     " keypoints (descriptors: " + std::to_string(descriptor_bytes) +
                     " bytes each), got " + std::to_string(descriptors.size()) +
                     " descriptor bytes, " + std::to_string(inverse_depth.size()) + " depths, " +
                     std::to_string(scales.size()) + " scales");
}

namespace {
std::vector<double> flatten(const std::vector<Eigen::Matrix3d>& m) {
  std::vector<double> out(9 * m.size());
  for (size_t i = 0; i < m.size(); ++i) Eigen::Map<Eigen::Matrix3d>(out.data() + 9 * i) = m[i];
  return out;
}
bool unflatten(const std::vector<double>& v, std::vector<Eigen::Matrix3d>& m) {
  if (v.size() % 9 != 0) return false;
  m.resize(v.size() / 9);
  for (size_t i = 0; i < m.size(); ++i) m[i] = Eigen::Map<const Eigen::Matrix3d>(v.data() + 9 * i);
  return true;
}
}  // namespace

void save(OutArchive& ar, const PinholeCamera& c) {
  ar.beginObject();
  ar.field("fx", c.fx).field("fy", c.fy).field("cx", c.cx).field("cy", c.cy);
  ar.field("baseline", c.baseline);
  ar.endObject();
}

void load(InArchive& ar, PinholeCamera& c) {
  ar.beginObject();
  ar.field("fx", c.fx).field("fy", c.fy).field("cx", c.cx).field("cy", c.cy);
  ar.field("baseline", c.baseline);
  ar.endObject();
}

void save(OutArchive& ar, const FeatureSet& f) {
  f.checkConsistent();
  ar.beginObject();
  ar.field("camera", f.camera).field("width", f.width).field("height", f.height);
  ar.field("mount", f.mount).field("stamp", f.stamp);
  ar.field("pixels", f.pixels).field("pixel_sigma", f.pixel_sigma);
  ar.field("scales", f.scales).field("max_scale", f.max_scale);
  ar.field("inverse_depth", f.inverse_depth).field("inverse_depth_sigma", f.inverse_depth_sigma);
  ar.field("points", f.points).field("covariances", flatten(f.covariances));
  ar.field("descriptor_bytes", f.descriptor_bytes);
  ar.field("descriptors", detail::toBase64(f.descriptors.data(), f.descriptors.size()));
  ar.field("colours", f.colours);
  ar.endObject();
}

void load(InArchive& ar, FeatureSet& f) {
  ar.beginObject();
  ar.field("camera", f.camera).field("width", f.width).field("height", f.height);
  ar.field("mount", f.mount).field("stamp", f.stamp);
  ar.field("pixels", f.pixels).field("pixel_sigma", f.pixel_sigma);
  // Feature sets saved before the image pyramid have no scales: every keypoint is full
  // resolution.
  const std::vector<std::string> keys = ar.keys();
  if (std::find(keys.begin(), keys.end(), "scales") != keys.end()) {
    ar.field("scales", f.scales).field("max_scale", f.max_scale);
  } else {
    f.scales.assign(f.pixels.size(), 1.0);
    f.max_scale = 1.0;
  }
  ar.field("inverse_depth", f.inverse_depth).field("inverse_depth_sigma", f.inverse_depth_sigma);
  ar.field("points", f.points);
  std::vector<double> cov;
  ar.field("covariances", cov);
  if (!unflatten(cov, f.covariances)) ar.fail("FeatureSet: covariances must be 9 values each");
  ar.field("descriptor_bytes", f.descriptor_bytes);
  std::string text;
  ar.field("descriptors", text);
  if (!detail::fromBase64(text, f.descriptors)) ar.fail("FeatureSet: descriptors are not base64");
  ar.field("colours", f.colours);
  try {
    f.checkConsistent();
  } catch (const InputError& e) {
    ar.fail(e.what());
  }
  ar.endObject();
}

}  // namespace abi_v1
}  // namespace plugslam
