#pragma once
// Test scenes for the dense depth code: exact z-depth images of a box-shaped room (or any set of
// planes) ray-cast through a small pinhole from a given camera pose.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "plugslam/geometry.h"
#include "plugslam/sensor_data.h"

namespace plugslam::rgbd::testing {

constexpr int kW = 320, kH = 240;
constexpr double kF = 260.0, kCx = 159.5, kCy = 119.5;

inline CameraIntrinsics pinhole() { return CameraIntrinsics{kF, kF, kCx, kCy, kW, kH, {}}; }

struct Plane {
  Eigen::Vector3d n;
  double d;  // n . p = d, in the world (the identity camera's frame)
};

// A room 4 m wide, 2.7 m high and 5 m deep around the identity camera (y down, z forward).
inline std::vector<Plane> room() {
  return {{{1, 0, 0}, 2.0},  {{-1, 0, 0}, 2.0}, {{0, 1, 0}, 1.2},
          {{0, -1, 0}, 1.5}, {{0, 0, 1}, 4.0},  {{0, 0, -1}, 1.0}};
}

// z-depth seen by a camera at `pose` (world <- camera), the nearest plane along each ray, with
// Gaussian noise of `noise` metres.
inline DepthImage render(const std::vector<Plane>& planes, const SE3& pose, double noise = 0,
                         unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  DepthImage img;
  img.resize(kW, kH);
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) {
      const Eigen::Vector3d ray((u - kCx) / kF, (v - kCy) / kF, 1.0);
      const Eigen::Vector3d dir = pose.linear() * ray;
      double best = std::numeric_limits<double>::infinity();
      for (const Plane& p : planes) {
        const double den = p.n.dot(dir);
        if (std::abs(den) < 1e-12) continue;
        const double t = (p.d - p.n.dot(pose.translation())) / den;
        if (t > 1e-3 && t < best) best = t;
      }
      if (std::isfinite(best))
        img.data[static_cast<size_t>(v * kW + u)] = static_cast<float>(best + noise * g(rng));
    }
  return img;
}

inline SE3 motion(const Eigen::Vector3d& axis_angle, const Eigen::Vector3d& t) {
  SE3 x = SE3::Identity();
  x.linear() = so3Exp(axis_angle);
  x.translation() = t;
  return x;
}

// A camera at `eye` looking at `target` (world <- camera; y down, z forward, the world's y down).
inline SE3 lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - eye).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z).normalized();
  SE3 pose = SE3::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = z.cross(x);
  pose.linear().col(2) = z;
  pose.translation() = eye;
  return pose;
}

// The corner of the room's far wall, right wall and floor.
inline const Eigen::Vector3d kCorner(2.0, 1.2, 4.0);

// The camera at the room's origin looking into the corner: three planes fill the image.
inline SE3 cornerView() { return lookAt({0.0, 0.0, 0.0}, kCorner); }

inline double degrees(const SE3& x) { return so3Log(x.linear()).norm() * 180.0 / M_PI; }

}  // namespace plugslam::rgbd::testing
