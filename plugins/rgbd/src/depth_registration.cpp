#include "depth_registration.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
namespace rgbd {
namespace {

cv::Matx33d cameraMatrix(const CameraIntrinsics& c) {
  return cv::Matx33d(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
}

bool sameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.width == b.width &&
         a.height == b.height && a.distortion.model == b.distortion.model &&
         a.distortion.coefficients == b.distortion.coefficients;
}

void checkModel(const CameraIntrinsics& c, const char* which) {
  if (c.distortion.model != Distortion::Model::kNone && !c.distortion.valid())
    throw InputError(std::string("rgbd: the ") + which + " camera's " +
                     distortionModelName(c.distortion.model) + " distortion has " +
                     std::to_string(c.distortion.coefficients.size()) + " coefficients");
  if (!(c.fx > 0) || !(c.fy > 0) || c.width < 1 || c.height < 1)
    throw InputError(std::string("rgbd: the ") + which +
                     " camera needs fx, fy > 0 and an image size");
}

}  // namespace

void undistortPixels(const CameraIntrinsics& c, std::vector<double>& xy) {
  if (c.distortion.isIdentity() || xy.empty()) return;
  cv::Mat src(static_cast<int>(xy.size() / 2), 1, CV_64FC2, xy.data());
  cv::Mat dst;
  const cv::Matx33d K = cameraMatrix(c);
  const cv::Mat D(c.distortion.coefficients, true);
  if (c.distortion.model == Distortion::Model::kEquidistant) {
    cv::fisheye::undistortPoints(src, dst, K, D, cv::noArray(), K);
  } else {
    // More iterations than the default 5: strong wide-angle distortion converges slowly.
    cv::undistortPoints(src, dst, K, D, cv::noArray(), K,
                        cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 20, 1e-9));
  }
  dst.reshape(1, 1).copyTo(cv::Mat(1, static_cast<int>(xy.size()), CV_64F, xy.data()));
}

bool DepthRegistration::sameCalibration(const CameraInfo& c) const {
  return prepared_ && sameIntrinsics(c.intrinsics(), camera_.intrinsics()) &&
         c.second.has_value() == camera_.second.has_value() &&
         (!c.second || sameIntrinsics(*c.second, *camera_.second)) &&
         c.second_pose.matrix() == camera_.second_pose.matrix();
}

void DepthRegistration::prepare(const CameraInfo& camera) {
  if (sameCalibration(camera)) return;
  camera_ = camera;
  prepared_ = true;
  const CameraIntrinsics colour = camera.intrinsics();
  checkModel(colour, "colour");
  // A calibration without a second camera (written before plugin ABI 1.5) is registered depth.
  const CameraIntrinsics depth = camera.second ? *camera.second : colour;
  checkModel(depth, "depth");
  identity_ = sameIntrinsics(colour, depth) && camera.second_pose.isApprox(
                                                   Eigen::Isometry3d::Identity(), 1e-12);
  bearings_.clear();
  if (identity_) return;
  const size_t n = static_cast<size_t>(depth.width) * static_cast<size_t>(depth.height);
  std::vector<double> xy(2 * n);
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u) {
      const size_t i = static_cast<size_t>(v) * static_cast<size_t>(depth.width) +
                       static_cast<size_t>(u);
      xy[2 * i] = u;
      xy[2 * i + 1] = v;
    }
  undistortPixels(depth, xy);
  bearings_.resize(2 * n);
  for (size_t i = 0; i < n; ++i) {
    bearings_[2 * i] = static_cast<float>((xy[2 * i] - depth.cx) / depth.fx);
    bearings_[2 * i + 1] = static_cast<float>((xy[2 * i + 1] - depth.cy) / depth.fy);
  }
}

const DepthImage& DepthRegistration::apply(const DepthImage& depth) {
  if (!prepared_) throw InputError("rgbd: DepthRegistration::apply before prepare");
  if (identity_) return depth;
  const CameraIntrinsics colour = camera_.intrinsics();
  const CameraIntrinsics& dk = *camera_.second;
  if (depth.width != dk.width || depth.height != dk.height)
    throw InputError("rgbd: depth image is " + std::to_string(depth.width) + "x" +
                     std::to_string(depth.height) + ", its calibration says " +
                     std::to_string(dk.width) + "x" + std::to_string(dk.height));
  out_.resize(colour.width, colour.height);
  out_.stamp = depth.stamp;
  const Eigen::Matrix3f R = camera_.second_pose.linear().cast<float>();
  const Eigen::Vector3f t = camera_.second_pose.translation().cast<float>();
  // Points in the colour camera's frame, then their raw pixels in the colour image.
  std::vector<cv::Point3f> points;
  points.reserve(depth.data.size());
  for (size_t i = 0; i < depth.data.size(); ++i) {
    const float z = depth.data[i];
    if (!(z > 0)) continue;
    const Eigen::Vector3f q = R * Eigen::Vector3f(bearings_[2 * i] * z, bearings_[2 * i + 1] * z, z) + t;
    if (q.z() > 0) points.emplace_back(q.x(), q.y(), q.z());
  }
  std::vector<cv::Point2f> pixels(points.size());
  if (colour.distortion.isIdentity()) {
    for (size_t k = 0; k < points.size(); ++k)
      pixels[k] = cv::Point2f(static_cast<float>(colour.fx * points[k].x / points[k].z + colour.cx),
                              static_cast<float>(colour.fy * points[k].y / points[k].z + colour.cy));
  } else if (!points.empty()) {
    const cv::Matx33d K = cameraMatrix(colour);
    const cv::Mat D(colour.distortion.coefficients, true);
    const cv::Vec3d zero(0, 0, 0);
    if (colour.distortion.model == Distortion::Model::kEquidistant)
      cv::fisheye::projectPoints(points, pixels, zero, zero, K, D);
    else
      cv::projectPoints(points, zero, zero, K, D, pixels);
  }
  // Each point covers the 2x2 colour pixels around it, so a depth camera of lower resolution
  // leaves no holes; the nearest surface wins (a z-buffer), as the colour camera sees it.
  std::fill(out_.data.begin(), out_.data.end(), std::numeric_limits<float>::infinity());
  for (size_t k = 0; k < points.size(); ++k) {
    const int u0 = static_cast<int>(std::floor(pixels[k].x));
    const int v0 = static_cast<int>(std::floor(pixels[k].y));
    for (int v = v0; v <= v0 + 1; ++v) {
      if (v < 0 || v >= colour.height) continue;
      for (int u = u0; u <= u0 + 1; ++u) {
        if (u < 0 || u >= colour.width) continue;
        float& cell = out_.data[static_cast<size_t>(v) * static_cast<size_t>(colour.width) +
                                static_cast<size_t>(u)];
        cell = std::min(cell, points[k].z);
      }
    }
  }
  for (float& z : out_.data)
    if (std::isinf(z)) z = 0.0f;
  return out_;
}

}  // namespace rgbd
}  // namespace plugslam
