// Depth registered to colour: the identity needs nothing; a depth camera of its own (another
// pinhole, resolution, lens distortion, a few centimetres and a degree apart) is moved into the
// colour camera's pixels and agrees with the depth the colour camera itself would see.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <vector>

#include "depth_registration.h"
#include "sim3d/renderer.h"
#include "sim3d/simulator.h"

namespace plugslam::rgbd {
namespace {

CameraIntrinsics intrinsics(double f, double cx, double cy, int w, int h) {
  CameraIntrinsics c;
  c.fx = c.fy = f;
  c.cx = cx;
  c.cy = cy;
  c.width = w;
  c.height = h;
  return c;
}

// The depth camera 2.5 cm left of the colour camera (a Kinect v1's spacing), turned by 1 degree.
Eigen::Isometry3d depthPose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(-0.025, 0.002, 0.001);
  T.linear() = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d(0.2, 1, 0).normalized()).matrix();
  return T;
}

double percentile(std::vector<double> v, double p) {
  const size_t k = static_cast<size_t>(p * static_cast<double>(v.size() - 1));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

TEST(DepthRegistration, RegisteredDepthIsReturnedAsItIs) {
  CameraInfo cam;
  cam.setIntrinsics(intrinsics(525, 319.5, 239.5, 640, 480));
  cam.second = cam.intrinsics();
  DepthRegistration r;
  r.prepare(cam);
  EXPECT_TRUE(r.identity());
  DepthImage d;
  d.resize(640, 480);
  EXPECT_EQ(&r.apply(d), &d);
  CameraInfo old = cam;  // a calibration written before the depth camera was part of it
  old.second.reset();
  r.prepare(old);
  EXPECT_TRUE(r.identity());
  cam.second_pose.translation().x() = 0.025;
  r.prepare(cam);
  EXPECT_FALSE(r.identity());
}

TEST(DepthRegistration, RenderedRoomSeenByASeparateDepthCamera) {
  sim::sim3d::ScenarioOptions o;
  const auto sim = sim::sim3d::Simulator3D::fromOptions(o);
  const Eigen::Isometry3d pose = sim.trajectory().poses()[0].pose;
  const sim::sim3d::PinholeCamera colour = sim.camera();
  sim::sim3d::PinholeCamera dcam;  // a quarter of the pixels, another focal length
  dcam.fx = dcam.fy = 290;
  dcam.cx = 159.5;
  dcam.cy = 119.5;
  dcam.width = 320;
  dcam.height = 240;
  sim::sim3d::RenderOptions ro;
  ro.shade = false;
  sim::sim3d::RenderBuffers seen, truth;
  sim::sim3d::render(sim.world(), dcam, pose * depthPose(), &seen, nullptr, ro);
  sim::sim3d::render(sim.world(), colour, pose, &truth, nullptr, ro);
  DepthImage d;
  d.resize(dcam.width, dcam.height);
  for (size_t i = 0; i < d.data.size(); ++i) d.data[i] = static_cast<float>(seen.depth[i]);

  CameraInfo cam;
  cam.setIntrinsics(intrinsics(colour.fx, colour.cx, colour.cy, colour.width, colour.height));
  cam.second = intrinsics(dcam.fx, dcam.cx, dcam.cy, dcam.width, dcam.height);
  cam.second_pose = depthPose();
  DepthRegistration r;
  r.prepare(cam);
  ASSERT_FALSE(r.identity());
  const DepthImage& out = r.apply(d);
  ASSERT_EQ(out.width, colour.width);
  // Coverage counts the colour pixels whose surface point lies inside the depth camera's image
  // (its view is narrower: 82 % of the colour image here); the others cannot get depth.
  const Eigen::Isometry3d depth_from_colour = depthPose().inverse();
  std::vector<double> errors;
  size_t in_view = 0, covered = 0;
  for (size_t i = 0; i < out.data.size(); ++i) {
    if (!(truth.depth[i] > 0)) continue;
    if (out.data[i] > 0) errors.push_back(std::abs(out.data[i] - truth.depth[i]));
    const double u = static_cast<double>(i % static_cast<size_t>(colour.width));
    const double v = static_cast<double>(i / static_cast<size_t>(colour.width));
    const Eigen::Vector3d q = depth_from_colour * (truth.depth[i] * Eigen::Vector3d(
                                                       (u - colour.cx) / colour.fx,
                                                       (v - colour.cy) / colour.fy, 1.0));
    const double ud = dcam.fx * q.x() / q.z() + dcam.cx, vd = dcam.fy * q.y() / q.z() + dcam.cy;
    if (!(q.z() > 0) || ud < 1 || vd < 1 || ud > dcam.width - 2 || vd > dcam.height - 2) continue;
    ++in_view;
    covered += out.data[i] > 0;
  }
  // What the depth camera sees is covered without holes, but for the surfaces it does not see
  // behind an edge (occlusions between cameras 2.5 cm apart).
  ASSERT_GT(in_view, out.data.size() / 2);
  EXPECT_GT(static_cast<double>(covered) / static_cast<double>(in_view), 0.95);
  // Each depth pixel lands within half a colour pixel of where the colour camera sees its point:
  // on slanted surfaces that is a few millimetres, at occlusion edges (the nearest of the 2x2
  // splat wins) up to the depth step. Measured median 1.1 mm, 95th percentile 9 mm.
  EXPECT_LT(percentile(errors, 0.5), 0.003);
  EXPECT_LT(percentile(errors, 0.95), 0.03);
}

// Depth of the plane n . p = d at each pixel of a camera with lens distortion.
DepthImage planeSeenBy(const CameraIntrinsics& c, const Eigen::Isometry3d& T_plane_cam,
                       const Eigen::Vector3d& n, double d) {
  std::vector<double> xy;
  for (int v = 0; v < c.height; ++v)
    for (int u = 0; u < c.width; ++u) {
      xy.push_back(u);
      xy.push_back(v);
    }
  undistortPixels(c, xy);
  DepthImage img;
  img.resize(c.width, c.height);
  // In the camera's frame the plane is n_c . p = d_c.
  const Eigen::Vector3d nc = T_plane_cam.linear().transpose() * n;
  const double dc = d - n.dot(T_plane_cam.translation());
  for (size_t i = 0; i < img.data.size(); ++i) {
    const Eigen::Vector3d ray((xy[2 * i] - c.cx) / c.fx, (xy[2 * i + 1] - c.cy) / c.fy, 1);
    const double z = dc / nc.dot(ray);
    img.data[i] = z > 0 ? static_cast<float>(z) : 0.0f;
  }
  return img;
}

TEST(DepthRegistration, LensDistortionOfBothCamerasIsUndone) {
  CameraIntrinsics colour = intrinsics(517.3, 318.6, 255.3, 640, 480);
  colour.distortion.model = Distortion::Model::kRadialTangential;
  colour.distortion.coefficients = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};  // TUM fr1 RGB
  CameraIntrinsics depth = intrinsics(591.1, 331.0, 234.0, 640, 480);
  depth.distortion.model = Distortion::Model::kRadialTangential;
  depth.distortion.coefficients = {-0.0410, 0.3286, 0.0087, 0.0051, -0.5643};  // TUM fr1 depth
  CameraInfo cam;
  cam.setIntrinsics(colour);
  cam.second = depth;
  cam.second_pose = depthPose();
  const Eigen::Vector3d n = Eigen::Vector3d(0.2, -0.1, -1).normalized();  // a wall, 20 deg off
  const double dist = -1.8;
  const DepthImage seen = planeSeenBy(depth, cam.second_pose, n, dist);
  const DepthImage truth = planeSeenBy(colour, Eigen::Isometry3d::Identity(), n, dist);
  DepthRegistration r;
  r.prepare(cam);
  const DepthImage& out = r.apply(seen);
  std::vector<double> errors;
  for (size_t i = 0; i < out.data.size(); ++i)
    if (out.data[i] > 0 && truth.data[i] > 0)
      errors.push_back(std::abs(out.data[i] - truth.data[i]));
  // Coverage counts the colour pixels whose point on the plane lies inside the depth image (the
  // depth camera's longer focal length sees 81 % of the colour image): each colour pixel's ray
  // (its distortion undone), at the true depth, into the depth camera's raw pixels.
  std::vector<double> xy;
  for (int v = 0; v < colour.height; ++v)
    for (int u = 0; u < colour.width; ++u) {
      xy.push_back(u);
      xy.push_back(v);
    }
  undistortPixels(colour, xy);
  std::vector<cv::Point3d> points;
  std::vector<size_t> index;
  const Eigen::Isometry3d depth_from_colour = cam.second_pose.inverse();
  for (size_t i = 0; i < truth.data.size(); ++i) {
    if (!(truth.data[i] > 0)) continue;
    const Eigen::Vector3d q =
        depth_from_colour * (static_cast<double>(truth.data[i]) *
                             Eigen::Vector3d((xy[2 * i] - colour.cx) / colour.fx,
                                             (xy[2 * i + 1] - colour.cy) / colour.fy, 1.0));
    points.emplace_back(q.x(), q.y(), q.z());
    index.push_back(i);
  }
  std::vector<cv::Point2d> raw;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                    cv::Matx33d(depth.fx, 0, depth.cx, 0, depth.fy, depth.cy, 0, 0, 1),
                    cv::Mat(depth.distortion.coefficients), raw);
  size_t in_view = 0, covered = 0;
  for (size_t k = 0; k < raw.size(); ++k) {
    if (raw[k].x < 1 || raw[k].y < 1 || raw[k].x > depth.width - 2 || raw[k].y > depth.height - 2)
      continue;
    ++in_view;
    covered += out.data[index[k]] > 0;
  }
  // A continuous plane: the error is the depth change over the < 1 px the splat moves a point;
  // every pixel in view is covered. Without undoing the distortion the image corners are
  // pixels off (centimetres of depth on this slant).
  ASSERT_GT(in_view, out.data.size() / 2);
  EXPECT_GT(static_cast<double>(covered) / static_cast<double>(in_view), 0.97);
  EXPECT_LT(percentile(errors, 0.5), 0.002);
  EXPECT_LT(*std::max_element(errors.begin(), errors.end()), 0.008);
}

TEST(UndistortPixels, InvertsOpenCvsProjection) {
  CameraIntrinsics c = intrinsics(517.3, 318.6, 255.3, 640, 480);
  c.distortion.model = Distortion::Model::kRadialTangential;
  c.distortion.coefficients = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
  std::vector<cv::Point3d> rays;
  for (double y = -0.4; y <= 0.4; y += 0.2)
    for (double x = -0.55; x <= 0.55; x += 0.11) rays.emplace_back(x, y, 1.0);
  std::vector<cv::Point2d> raw;
  const cv::Matx33d K(c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1);
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K,
                    cv::Mat(c.distortion.coefficients), raw);
  std::vector<double> xy;
  for (const auto& p : raw) {
    xy.push_back(p.x);
    xy.push_back(p.y);
  }
  undistortPixels(c, xy);
  for (size_t k = 0; k < rays.size(); ++k) {
    EXPECT_NEAR(xy[2 * k], c.fx * rays[k].x + c.cx, 1e-3) << k;
    EXPECT_NEAR(xy[2 * k + 1], c.fy * rays[k].y + c.cy, 1e-3) << k;
  }
}

}  // namespace
}  // namespace plugslam::rgbd
