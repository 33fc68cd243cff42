#include "sim3d/mixed.h"

#include <cmath>
#include <limits>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim3d {

Eigen::Isometry3d MixedOptions::defaultCameraMount() {
  Eigen::Matrix3d base_R_optical;
  base_R_optical.col(0) = -Eigen::Vector3d::UnitY();  // image x: right of the robot
  base_R_optical.col(1) = -Eigen::Vector3d::UnitZ();  // image y: down
  base_R_optical.col(2) = Eigen::Vector3d::UnitX();   // optical axis: forward
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = base_R_optical *
               Eigen::AngleAxisd(-10.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.1, 0.0, 1.0);
  return T;
}

void castPlanarScan(const World& world, const Eigen::Isometry3d& base, double height,
                    const sim2d::LaserConfig& laser, sim2d::Rng* rng, LaserScan* scan) {
  const double yaw0 = std::atan2(base.linear()(1, 0), base.linear()(0, 0));
  const Eigen::Vector3d origin = base * Eigen::Vector3d(laser.mount.x(), laser.mount.y(), 0.0) +
                                 Eigen::Vector3d(0.0, 0.0, height - base.translation().z());
  scan->angle_min = laser.angleMin();
  scan->angle_increment = laser.angleIncrement();
  scan->range_min = laser.min_range;
  scan->range_max = laser.max_range;
  Eigen::Isometry2d mount = Eigen::Isometry2d::Identity();
  mount.linear() = Eigen::Rotation2Dd(laser.mount.z()).toRotationMatrix();
  mount.translation() = laser.mount.head<2>();
  scan->mount = mount;
  scan->ranges.assign(laser.beams, std::numeric_limits<double>::quiet_NaN());
  for (int i = 0; i < laser.beams; ++i) {
    const double a = yaw0 + laser.mount.z() + scan->angle_min + i * scan->angle_increment;
    const Eigen::Vector3d d(std::cos(a), std::sin(a), 0.0);
    RayHit hit;
    double r = std::numeric_limits<double>::quiet_NaN();
    if (world.castRay(origin, d, laser.max_range, &hit)) r = hit.distance;
    // Draw noise for every beam, hit or not, so the stream does not depend on the geometry.
    const double noise = rng ? rng->gaussian(laser.range_sigma) : 0.0;
    const bool drop = rng ? rng->bernoulli(laser.dropout) : false;
    if (!std::isfinite(r) || drop) continue;
    r += noise;
    if (r < laser.min_range || r > laser.max_range) continue;
    scan->ranges[i] = r;
  }
}

MixedSimulator::MixedSimulator(const MixedOptions& o)
    : options_(o), camera_(PinholeCamera::vga()), laser_rng_(o.seed, 200) {
  options_.laser.validate();
  if (!(o.laser_height > 0.0 && o.laser_height < 2.6))
    throw InputError("sim3d mixed: laser_height must be inside the room (0, 2.6) m");
  if (!(o.odometry_noise >= 0.0)) throw InputError("sim3d mixed: odometry_noise must be >= 0");
  world_ = std::make_shared<const World>(World::livingRoom(o.seed));
  // The floor plan the robot must avoid: cuts through everything up to its height (0.8 m).
  std::vector<sim2d::Segment> walls;
  for (double z : {0.05, o.laser_height, 0.42, 0.76})
    for (const auto& [a, b] : world_->slice(z)) walls.push_back({a, b});
  sim2d::SimConfig c;
  c.world = std::make_shared<const sim2d::World>(std::move(walls));
  c.tour = {{1.2, 1.6}, {4.0, 1.3}, {7.2, 0.9}, {7.2, 3.6}, {4.5, 4.6}, {3.6, 3.0}};
  c.path_length = o.path_length;
  c.rate = o.rate;
  c.drive.max_linear = 0.4;
  c.drive.max_angular = 0.8;
  c.planner.min_clearance = 0.4;
  c.planner.preferred_clearance = 0.8;
  c.lasers = {};
  c.odometry = c.odometry.scaled(o.odometry_noise);
  c.seed = o.seed;
  sim2d_ = std::make_unique<sim2d::Simulator>(std::move(c));
  options_.depth_noise.validate();
  options_.image_noise.validate();
}

CameraInfo MixedSimulator::cameraInfo() const {
  CameraInfo c = camera_.info();
  c.mount = options_.camera_mount;
  return c;
}

bool MixedSimulator::step(MixedFrame* f) {
  sim2d::SimFrame s;
  if (!sim2d_->step(s)) return false;
  f->index = s.index;
  f->stamp = s.time;
  f->base = Eigen::Isometry3d::Identity();
  f->base.linear() =
      Eigen::AngleAxisd(s.ground_truth.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  f->base.translation() = Eigen::Vector3d(s.ground_truth.x(), s.ground_truth.y(), 0.0);
  f->odometry = sim2d::toIsometry(s.odometry);
  f->scan.stamp = s.time;
  castPlanarScan(*world_, f->base, options_.laser_height, options_.laser, &laser_rng_, &f->scan);
  f->scan.stamp = s.time;
  f->rgb.channels = 3;
  RenderBuffers buffers;
  render(*world_, camera_, f->base * options_.camera_mount, &buffers, &f->rgb);
  applyImageNoise(options_.image_noise, options_.seed, s.index, 0,
                  exposureGain(options_.image_noise, options_.seed, s.time), &f->rgb);
  makeDepthImage(buffers, options_.depth_noise, options_.seed, s.index, &f->depth);
  f->rgb.stamp = f->depth.stamp = s.time;
  return true;
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
