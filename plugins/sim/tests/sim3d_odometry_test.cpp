// The 3D simulator's wheel odometry (sim3d/odometry.h, sim.Simulator3D's `odometry`): the
// vehicle's ground-plane motion with sim2d's wheel-encoder errors, whose statistics follow the
// parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "plugslam/pose_space.h"
#include "sim3d/odometry.h"
#include "sim3d/trajectory.h"
#include "sim3d/world.h"
#include "simulator3d_source.h"

namespace plugslam::sim {
namespace {

// A camera 1.65 m up, `steps` poses, each `step` metres ahead and turned `turn` radians (about
// the world's up) from the previous.
Trajectory drive(int steps, double step, double turn) {
  Trajectory t;
  Eigen::Isometry2d base = Eigen::Isometry2d::Identity();
  const Eigen::Isometry3d camera_in_base = sim3d::cameraInVehicle(sim3d::kCameraHeight);
  for (int k = 0; k < steps; ++k) {
    t.push_back(0.1 * k, Space2D::to3D(base) * camera_in_base);
    base = base * se2(step, 0.0, turn);
  }
  return t;
}

struct Moments {
  double mean = 0, sd = 0;
};

Moments moments(const std::vector<double>& x) {
  Moments m;
  for (double v : x) m.mean += v;
  m.mean /= x.size();
  for (double v : x) m.sd += (v - m.mean) * (v - m.mean);
  m.sd = std::sqrt(m.sd / (x.size() - 1));
  return m;
}

// Per-step errors of the readings against the true step (distance, heading).
void stepErrors(const std::vector<Eigen::Isometry2d>& odom, const Eigen::Isometry2d& truth,
                std::vector<double>* along, std::vector<double>* heading) {
  for (size_t k = 1; k < odom.size(); ++k) {
    const Eigen::Isometry2d d = odom[k - 1].inverse() * odom[k];
    along->push_back(d.translation().x() - truth.translation().x());
    heading->push_back(angleOf(d.linear()) - angleOf(truth.linear()));
  }
}

sim3d::WheelOdometryOptions strongNoise() {
  // Larger than the preset, so the expected statistics stand far above the estimates' spread.
  sim3d::WheelOdometryOptions o;
  o.noise.left_scale_error = 0.01;
  o.noise.right_scale_error = 0.03;
  o.noise.wheel_base_error = 0.05;
  o.noise.slip_per_distance = 0.01;
  o.noise.slip_per_rotation = 0.02;
  o.wheel_base = 1.6;
  o.seed = 7;
  return o;
}

TEST(Sim3dOdometry, WithoutNoiseItIsTheGroundPlaneProjectionOfTheTruth) {
  // The generated street drive (corners included) and a climbing, rolling camera: the readings
  // are the base's x, y, yaw exactly, each step projected onto the base's own plane.
  sim3d::WheelOdometryOptions o;
  o.noise = sim2d::OdometryNoise::none();
  const Trajectory street =
      sim3d::driveAlong(sim3d::blockLoop(160.0, 100.0, 12.0, 2.0), sim3d::kCameraHeight, 8.0, 10.0);
  const std::vector<Eigen::Isometry2d> odom = sim3d::wheelOdometry(street, o);
  ASSERT_EQ(odom.size(), street.size());
  const Eigen::Isometry3d to_base = sim3d::cameraInVehicle(sim3d::kCameraHeight).inverse();
  for (size_t k = 0; k < street.size(); ++k) {
    const Eigen::Isometry2d truth = Space2D::from3D(street[k].pose * to_base);
    ASSERT_LT((truth.translation() - odom[k].translation()).norm(), 1e-9) << k;
    ASSERT_LT(std::abs(angleOf(truth.linear().transpose() * odom[k].linear())), 1e-9) << k;
  }
  // On a 5 % climb the wheels measure the distance along the road, not its horizontal part.
  Trajectory climb;
  for (int k = 0; k < 11; ++k)
    climb.push_back(0.1 * k, sim3d::lookAlong(Eigen::Vector3d(k, 0.0, 1.65 + 0.05 * k),
                                              Eigen::Vector3d(1.0, 0.0, 0.05)));
  const std::vector<Eigen::Isometry2d> up = sim3d::wheelOdometry(climb, o);
  const Eigen::Isometry2d travelled = up.front().inverse() * up.back();
  EXPECT_NEAR(travelled.translation().x(), 10.0 * std::sqrt(1.0 + 0.05 * 0.05), 1e-9);
  EXPECT_NEAR(travelled.translation().y(), 0.0, 1e-9);
}

TEST(Sim3dOdometry, StraightDriveScaleAndHeadingNoiseMatchTheParameters) {
  // Each 1 m step: wheel travels 1 (1 + scale) + N(0, slip^2 * 1 m). Distance: mean scale error
  // (l + r) / 2, sd slip / sqrt(2); heading: mean (r - l) / b', sd slip sqrt(2) / b', with
  // b' = b (1 + wheel_base_error) the base the integrator believes.
  const sim3d::WheelOdometryOptions o = strongNoise();
  const int n = 20000;
  std::vector<double> along, heading;
  stepErrors(sim3d::wheelOdometry(drive(n, 1.0, 0.0), o), se2(1.0, 0.0, 0.0), &along, &heading);
  const double b = o.wheel_base * (1 + o.noise.wheel_base_error), s = o.noise.slip_per_distance;
  const Moments a = moments(along), h = moments(heading);
  const double sqrt_n = std::sqrt(static_cast<double>(n));
  EXPECT_NEAR(a.mean, 0.02, 5 * s / std::sqrt(2.0) / sqrt_n);
  EXPECT_NEAR(a.sd, s / std::sqrt(2.0), 0.03 * s / std::sqrt(2.0));
  EXPECT_NEAR(h.mean, 0.02 / b, 5 * s * std::sqrt(2.0) / b / sqrt_n);
  EXPECT_NEAR(h.sd, s * std::sqrt(2.0) / b, 0.03 * s * std::sqrt(2.0) / b);
}

TEST(Sim3dOdometry, TurningInPlaceHeadingNoiseMatchesTheParameters) {
  // 0.1 rad steps in place: each wheel travels 0.05 b, with slip variance
  // slip_per_distance^2 * 0.05 b + slip_per_rotation^2 * 0.1 rad. The heading is scaled by
  // (1 + (l + r) / 2) / (1 + wheel_base_error), its sd is sqrt(2 var) / b'.
  const sim3d::WheelOdometryOptions o = strongNoise();
  const int n = 20000;
  std::vector<double> along, heading;
  stepErrors(sim3d::wheelOdometry(drive(n, 0.0, 0.1), o), se2(0.0, 0.0, 0.1), &along, &heading);
  const sim2d::OdometryNoise& e = o.noise;
  const double b = o.wheel_base * (1 + e.wheel_base_error);
  const double var = e.slip_per_distance * e.slip_per_distance * 0.05 * o.wheel_base +
                     e.slip_per_rotation * e.slip_per_rotation * 0.1;
  const double sd = std::sqrt(2 * var) / b;
  const Moments h = moments(heading);
  const double scale =
      (1 + 0.5 * (e.left_scale_error + e.right_scale_error)) / (1 + e.wheel_base_error);
  EXPECT_NEAR(h.mean, 0.1 * (scale - 1), 5 * sd / std::sqrt(static_cast<double>(n)));
  EXPECT_NEAR(h.sd, sd, 0.03 * sd);
}

TEST(Sim3dOdometry, TheNoiseIsSeeded) {
  sim3d::WheelOdometryOptions o = strongNoise();
  const Trajectory t = drive(50, 1.0, 0.02);
  const std::vector<Eigen::Isometry2d> a = sim3d::wheelOdometry(t, o),
                                       b = sim3d::wheelOdometry(t, o);
  o.seed = 8;
  const std::vector<Eigen::Isometry2d> c = sim3d::wheelOdometry(t, o);
  EXPECT_TRUE(a.back().isApprox(b.back(), 0.0));
  EXPECT_GT((a.back().translation() - c.back().translation()).norm(), 1e-6);
}

TEST(Sim3dOdometry, TheSourceWritesItOnlyWhenNamed) {
  Simulator3DSource off;
  off.world = std::string("street");
  off.camera = std::string("stereo");
  off.configure();
  for (const auto& e : off.provides()) EXPECT_NE(e.type, typeid(Odometry2D)) << e.name;

  Simulator3DSource on;
  on.world = std::string("street");
  on.camera = std::string("stereo");
  on.odometry = std::string("odom");
  on.configure();
  bool listed = false;
  for (const auto& e : on.provides()) listed |= e.name == "odom" && e.type == typeid(Odometry2D);
  EXPECT_TRUE(listed);
  Frame f0, f1;
  ASSERT_TRUE(on.next(f0));
  ASSERT_TRUE(on.next(f1));
  ASSERT_TRUE(f1.raw.holds<Odometry2D>("odom"));
  const Odometry2D& o0 = f0.raw.get<Odometry2D>("odom");
  const Odometry2D& o1 = f1.raw.get<Odometry2D>("odom");
  EXPECT_EQ(o1.stamp, f1.stamp);
  // 8 m/s at 10 Hz, straight ahead at the start, within the preset's errors.
  const Eigen::Isometry2d d = o0.pose.inverse() * o1.pose;
  EXPECT_NEAR(d.translation().x(), 0.8, 0.01);
  EXPECT_NEAR(d.translation().y(), 0.0, 0.01);
  Frame g;
  ASSERT_TRUE(off.next(g));
  EXPECT_FALSE(g.raw.has("odom"));

  Simulator3DSource clash;
  clash.odometry = std::string("ground_truth");
  EXPECT_THROW(clash.configure(), ParamError);
  clash.odometry = std::string("left");
  EXPECT_THROW(clash.configure(), ParamError);
}

}  // namespace
}  // namespace plugslam::sim
