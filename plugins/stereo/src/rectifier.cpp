#include "rectifier.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "plugslam/errors.h"

namespace plugslam {
namespace visual {

namespace {
cv::Matx33d cameraMatrix(double fx, double fy, double cx, double cy) {
  return cv::Matx33d(fx, 0, cx, 0, fy, cy, 0, 0, 1);
}

cv::Mat coefficients(const Distortion& d) {
  cv::Mat m(1, static_cast<int>(d.coefficients.size()), CV_64F);
  for (size_t i = 0; i < d.coefficients.size(); ++i) m.at<double>(0, static_cast<int>(i)) = d.coefficients[i];
  return m;
}

bool sameDistortion(const Distortion& a, const Distortion& b) {
  return a.model == b.model && a.coefficients == b.coefficients;
}

bool sameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.width == b.width &&
         a.height == b.height && sameDistortion(a.distortion, b.distortion);
}
}  // namespace

bool StereoRectifier::needed(const CameraInfo& raw) {
  return !(raw.baseline > 0) && raw.second.has_value();
}

bool StereoRectifier::same(const CameraInfo& raw) const {
  return ready_ && sameIntrinsics(raw.intrinsics(), raw_.intrinsics()) && raw_.second &&
         sameIntrinsics(*raw.second, *raw_.second) &&
         raw.second_pose.matrix() == raw_.second_pose.matrix() &&
         raw.mount.matrix() == raw_.mount.matrix();
}

void StereoRectifier::prepare(const CameraInfo& raw) {
  if (same(raw)) return;
  if (!raw.second) throw InputError("stereo: the calibration has no second (right) camera");
  const CameraIntrinsics& r = *raw.second;
  if (r.width != raw.width || r.height != raw.height)
    throw InputError("stereo: the right camera is calibrated at " + std::to_string(r.width) + "x" +
                     std::to_string(r.height) + " but the left at " + std::to_string(raw.width) +
                     "x" + std::to_string(raw.height));
  for (const Distortion* d : {&raw.distortion, &r.distortion})
    if (!d->valid())
      throw InputError(std::string("stereo: ") + distortionModelName(d->model) +
                       " distortion with " + std::to_string(d->coefficients.size()) +
                       " coefficients is not a valid model");
  if (raw.distortion.model != r.distortion.model &&
      !(raw.distortion.isIdentity() && r.distortion.isIdentity()))
    throw InputError("stereo: the two cameras use different distortion models");
  // OpenCV's R, T take left-camera points to the right camera: the inverse of second_pose.
  const Eigen::Isometry3d right_from_left = raw.second_pose.inverse();
  if (right_from_left.translation().norm() < 1e-6)
    throw InputError("stereo: both cameras are at the same place (second_pose has no translation)");
  cv::Matx33d rot;
  cv::Vec3d t;
  for (int i = 0; i < 3; ++i) {
    t[i] = right_from_left.translation()[i];
    for (int j = 0; j < 3; ++j) rot(i, j) = right_from_left.linear()(i, j);
  }
  const cv::Size size(raw.width, raw.height);
  const cv::Matx33d k1 = cameraMatrix(raw.fx, raw.fy, raw.cx, raw.cy);
  const cv::Matx33d k2 = cameraMatrix(r.fx, r.fy, r.cx, r.cy);
  cv::Mat r1, r2, p1, p2, q;
  // alpha 0: only valid pixels remain, so no keypoint sits on the black border of the remap.
  if (raw.distortion.model == Distortion::Model::kEquidistant) {
    const cv::Mat d1 = coefficients(raw.distortion), d2 = coefficients(r.distortion);
    cv::fisheye::stereoRectify(k1, d1, k2, d2, size, rot, t, r1, r2, p1, p2, q,
                               cv::CALIB_ZERO_DISPARITY, size, 0.0, 1.0);
    cv::fisheye::initUndistortRectifyMap(k1, d1, r1, p1, size, CV_16SC2, map_l1_, map_l2_);
    cv::fisheye::initUndistortRectifyMap(k2, d2, r2, p2, size, CV_16SC2, map_r1_, map_r2_);
  } else {
    const cv::Mat d1 = raw.distortion.model == Distortion::Model::kNone ? cv::Mat()
                                                                         : coefficients(raw.distortion);
    const cv::Mat d2 =
        r.distortion.model == Distortion::Model::kNone ? cv::Mat() : coefficients(r.distortion);
    cv::stereoRectify(k1, d1, k2, d2, size, rot, t, r1, r2, p1, p2, q, cv::CALIB_ZERO_DISPARITY,
                      0.0, size);
    cv::initUndistortRectifyMap(k1, d1, r1, p1, size, CV_16SC2, map_l1_, map_l2_);
    cv::initUndistortRectifyMap(k2, d2, r2, p2, size, CV_16SC2, map_r1_, map_r2_);
  }
  // Horizontal rectification puts the right camera at -P2(0,3) / fx along +x.
  const double fx = p1.at<double>(0, 0);
  const double baseline = -p2.at<double>(0, 3) / p2.at<double>(0, 0);
  if (!(baseline > 0))
    throw InputError("stereo: the second camera is not to the right of the first (rectified "
                     "baseline " + std::to_string(baseline) + " m); swap the left and right entries");
  rectified_ = CameraInfo();
  rectified_.fx = fx;
  rectified_.fy = p1.at<double>(1, 1);
  rectified_.cx = p1.at<double>(0, 2);
  rectified_.cy = p1.at<double>(1, 2);
  rectified_.width = raw.width;
  rectified_.height = raw.height;
  rectified_.baseline = baseline;
  // x_rect = R1 x_left: the rectified camera is the raw left one turned by R1^T.
  Eigen::Matrix3d r1e;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r1e(i, j) = r1.at<double>(i, j);
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.linear() = r1e.transpose();
  rectified_.mount = raw.mount * turn;
  CameraIntrinsics right_rect{rectified_.fx, rectified_.fy, rectified_.cx, rectified_.cy,
                              raw.width, raw.height, Distortion()};
  rectified_.second = right_rect;
  rectified_.second_pose = Eigen::Isometry3d::Identity();
  rectified_.second_pose.translation().x() = baseline;
  raw_ = raw;
  ready_ = true;
  ++preparations_;
}

void StereoRectifier::rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& left_out,
                              cv::Mat& right_out) const {
  if (!ready_) throw InputError("stereo: rectify() before prepare()");
  cv::remap(left, left_out, map_l1_, map_l2_, cv::INTER_LINEAR);
  cv::remap(right, right_out, map_r1_, map_r2_, cv::INTER_LINEAR);
}

}  // namespace visual
}  // namespace plugslam
