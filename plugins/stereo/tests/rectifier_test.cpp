// Rectification of a raw pair described the way EuRoC's calibration is (radial-tangential
// distortion, the right camera slightly turned): the rectified rig and its mount.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>

#include "plugslam/errors.h"
#include "rectifier.h"

namespace plugslam {
namespace {

CameraInfo rawPair() {
  const auto radtan = Distortion::Model::kRadialTangential;
  CameraInfo c;
  c.setIntrinsics({{458.654, 457.296, 367.215, 248.375, 752, 480},
                   {radtan, {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05}}});
  c.second = CameraIntrinsics{{457.587, 456.134, 379.999, 255.238, 752, 480},
                              {radtan, {-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05}}};
  // Right camera 11 cm to the right, turned by a fraction of a degree.
  c.second_pose = Eigen::Isometry3d::Identity();
  c.second_pose.linear() = Eigen::AngleAxisd(0.004, Eigen::Vector3d(0.3, 1, 0.2).normalized())
                               .toRotationMatrix();
  c.second_pose.translation() << 0.110, -0.0004, 0.0008;
  c.mount.translation() << -0.02, -0.06, 0.01;
  return c;
}

TEST(StereoRectifier, RectifiesARawPairOnce) {
  const CameraInfo raw = rawPair();
  EXPECT_TRUE(visual::StereoRectifier::needed(raw));
  visual::StereoRectifier rect;
  rect.prepare(raw);
  rect.prepare(raw);  // same calibration: the maps are kept
  EXPECT_EQ(rect.preparations(), 1);
  const CameraInfo& r = rect.rectified();
  EXPECT_FALSE(visual::StereoRectifier::needed(r));
  // The rectified baseline is the cameras' distance (the rotation is tiny).
  EXPECT_NEAR(r.baseline, raw.second_pose.translation().norm(), 1e-4);
  EXPECT_TRUE(r.distortion.isIdentity());
  // The mount keeps the camera's position and turns it by less than the pair's misalignment.
  EXPECT_NEAR((r.mount.translation() - raw.mount.translation()).norm(), 0, 1e-12);
  EXPECT_LT(Eigen::AngleAxisd(raw.mount.linear().transpose() * r.mount.linear()).angle(), 0.01);

  // A point seen by both raw cameras lands on one row of the rectified pair, at the disparity
  // of its depth along the rectified axis.
  const Eigen::Vector3d p_left(0.4, -0.3, 3.0);
  const Eigen::Vector3d p_right = raw.second_pose.inverse() * p_left;
  auto project = [](const CameraIntrinsics& k, const Eigen::Vector3d& p) {
    std::vector<cv::Point3d> obj{{p.x(), p.y(), p.z()}};
    std::vector<cv::Point2d> img;
    const cv::Matx33d km(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    cv::projectPoints(obj, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), km, k.distortion.coefficients,
                      img);
    return img[0];
  };
  const cv::Point2d ul = project(raw.intrinsics(), p_left), ur = project(*raw.second, p_right);
  // Raw pixels to rectified ones: render one-pixel images through the maps.
  cv::Mat left = cv::Mat::zeros(raw.height, raw.width, CV_8UC1), right = left.clone();
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      left.at<uint8_t>(cvRound(ul.y) + dy, cvRound(ul.x) + dx) = 255;
      right.at<uint8_t>(cvRound(ur.y) + dy, cvRound(ur.x) + dx) = 255;
    }
  cv::Mat rl, rr;
  rect.rectify(left, right, rl, rr);
  cv::Point maxl, maxr;
  cv::minMaxLoc(rl, nullptr, nullptr, nullptr, &maxl);
  cv::minMaxLoc(rr, nullptr, nullptr, nullptr, &maxr);
  // Pixel-rounded blobs: rows agree to 1 px, the disparity is fx b / z to 2 px.
  EXPECT_LE(std::abs(maxl.y - maxr.y), 1);
  const Eigen::Vector3d p_rect = r.mount.inverse() * raw.mount * p_left;
  EXPECT_NEAR(maxl.x - maxr.x, r.fx * r.baseline / p_rect.z(), 2.0);
  EXPECT_NEAR(maxl.x, r.fx * p_rect.x() / p_rect.z() + r.cx, 1.5);
  EXPECT_NEAR(maxl.y, r.fy * p_rect.y() / p_rect.z() + r.cy, 1.5);
}

TEST(StereoRectifier, RefusesACalibrationWithoutASecondCamera) {
  CameraInfo c = rawPair();
  c.second.reset();
  visual::StereoRectifier rect;
  EXPECT_THROW(rect.prepare(c), InputError);
  CameraInfo same = rawPair();
  same.second_pose = Eigen::Isometry3d::Identity();
  EXPECT_THROW(rect.prepare(same), InputError);
}

}  // namespace
}  // namespace plugslam
