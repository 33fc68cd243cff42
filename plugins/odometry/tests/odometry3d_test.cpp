// odometry.WheelOdometry3D and odometry.PriorSlice3D: the planar odometry lifted into a 3D
// robot frame (here, as in the stereo pipeline, a camera's optical frame on a vehicle).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "odometry_frames.h"
#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/multi_tracker.h"
#include "plugslam/slice_check.h"
#include "prior_slice.h"
#include "wheel_odometry.h"

using namespace plugslam;
using namespace plugslam::odometry;
using namespace odometry_test;

namespace {

// The stereo pipeline's robot frame is the left camera's optical frame (x right, y down, z
// forward); the vehicle's base is 1.65 m below it, x forward, z up: the base in the camera frame
// is a 120-degree rotation about (1, -1, 1) and 1.65 m along the camera's y.
const std::vector<double> kBaseInCamera{
    0.0, 1.65, 0.0, 1.2091995761561452, -1.2091995761561452, 1.2091995761561452};

Eigen::Isometry3d baseInCamera() {
  Vector6d v;
  for (int i = 0; i < 6; ++i) v[i] = kBaseInCamera[i];
  return se3(v);
}

void expectPose(const Eigen::Isometry3d& expected, const Eigen::Isometry3d& actual, double tol) {
  EXPECT_LT((expected.translation() - actual.translation()).norm(), tol)
      << expected.translation().transpose() << " vs " << actual.translation().transpose();
  EXPECT_LT(Eigen::AngleAxisd(expected.linear().transpose() * actual.linear()).angle(), tol);
}

TEST(WheelOdometry3D, TheMountIsTheCameraOnTheVehicle) {
  // Driving forward moves the camera along its optical axis; turning left (yaw about the base's
  // up) turns it about its -y (image down is y).
  const Eigen::Isometry3d m = baseInCamera();
  EXPECT_TRUE(m.linear().col(0).isApprox(Eigen::Vector3d::UnitZ(), 1e-12));   // base x: forward
  EXPECT_TRUE(m.linear().col(1).isApprox(-Eigen::Vector3d::UnitX(), 1e-12));  // base y: left
  EXPECT_TRUE(m.linear().col(2).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));  // base z: up
  WheelOdometry3D model;
  model.mount = kBaseInCamera;
  model.configure();
  model.predict(odomFrame(0, se2(0, 0, 0)));
  auto forward = model.predict(odomFrame(1, se2(2.0, 0, 0)));
  ASSERT_TRUE(forward);
  expectPose(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 2.0)), forward->mean, 1e-9);
  auto turn = model.predict(odomFrame(2, se2(2.0, 0, 0.3)));
  ASSERT_TRUE(turn);
  Eigen::Isometry3d expected = Eigen::Isometry3d::Identity();
  expected.linear() = Eigen::AngleAxisd(0.3, -Eigen::Vector3d::UnitY()).toRotationMatrix();
  // The base turns about its own up axis, 1.65 m below the camera: the camera turns in place.
  expectPose(expected, turn->mean, 1e-9);
}

TEST(WheelOdometry3D, DeltasComposeBackToTheCameraPath) {
  // A planar drive of the base; the camera path it implies is base * mount^-1. The model's
  // deltas, composed from the first camera pose, recover it exactly.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Isometry2d> path{se2(2.0, -1.0, 0.3)};
  for (int i = 0; i < 50; ++i)
    path.push_back(path.back() * se2(1.0 + 0.5 * u(rng), 0.05 * u(rng), 0.2 * u(rng)));
  const Eigen::Isometry3d camera_in_base = baseInCamera().inverse();
  auto camera = [&](size_t i) { return Space2D::to3D(path[i]) * camera_in_base; };

  WheelOdometry3D model;
  model.mount = kBaseInCamera;
  model.configure();
  EXPECT_FALSE(model.predict(odomFrame(0, path[0])));
  Eigen::Isometry3d composed = camera(0);
  for (size_t i = 1; i < path.size(); ++i) {
    auto delta = model.predict(odomFrame(i, path[i]));
    ASSERT_TRUE(delta);
    composed = composed * delta->mean;
    expectPose(camera(i), composed, 1e-9);
  }
}

TEST(WheelOdometry3D, ARejectedMountNamesTheParameter) {
  WheelOdometry3D model;
  model.mount = std::vector<double>{1, 2, 3};
  EXPECT_THROW(model.configure(), plugslam::ParamError);
  PriorSlice3D slice;
  slice.mount = std::vector<double>{0, 0, 0, 0, 0, NAN};
  EXPECT_THROW(slice.configure(), plugslam::ParamError);
}

TEST(PriorSlice3D, ItsFactorPassesTheSdkJacobianCheck) {
  // Also with a mount that has a lever arm (a base ahead of and beside the robot frame) and
  // estimates away from the prior in every direction, out of plane too.
  Vector6d lever;
  lever << 0.7, -1.3, 0.4, 0.3, -0.8, 1.9;
  for (const Eigen::Isometry3d& mount : {baseInCamera(), se3(lever)}) {
    PriorSlice3D slice;
    const Vector6d v = plugslam::toVector(mount);
    slice.mount = std::vector<double>(v.data(), v.data() + 6);
    slice.configure();
    Vector6d p;
    p << 4.0, -2.0, 1.0, 0.2, -0.4, 2.5;
    bindStep(slice, se3(p), se2(3, 1, 0.5), se2(3, 1, 0.5) * se2(1.2, 0.1, 0.4));
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int trial = 0; trial < 20; ++trial) {
      Vector6d dx;
      for (int k = 0; k < 6; ++k) dx[k] = (k < 3 ? 0.5 : 0.8) * u(rng);
      const Eigen::Isometry3d t = slice.prior() * se3(dx);
      const plugslam::SliceJacobianCheck r = plugslam::checkSliceJacobians(slice, t);
      EXPECT_EQ(r.factors, 1u);
      EXPECT_TRUE(r.ok()) << "trial " << trial << ": " << r;
    }
  }
}

TEST(PriorSlice3D, AloneInAMultiAlignerReturnsThePriorExactly) {
  auto slice = std::make_shared<PriorSlice3D>();
  slice->mount = kBaseInCamera;
  slice->configure();
  const Eigen::Isometry2d odom0 = se2(5.0, -3.0, 1.2), odom1 = odom0 * se2(0.8, 0.1, -0.7);
  Vector6d p, g;
  p << -2.0, 4.0, 1.0, 0.1, 0.2, -2.5;
  g << -1.0, 3.0, 1.3, 0.0, 0.3, -2.0;
  AlignContext<Space3D> ctx{se3(p), se3(g)};
  const auto result = alignSecondReading(slice, odom0, odom1, ctx);
  const Eigen::Isometry3d m = baseInCamera();
  const Eigen::Isometry3d z =
      ctx.previous * m * Space2D::to3D(odom0.inverse() * odom1) * m.inverse();
  expectPose(z, result.pose, 1e-9);
  expectExactPrior(result);
}

TEST(PriorSlice3D, WeighsTheBasesPlanarMotionAsPriorSliceAndTheRestLoosely) {
  // The same sigma model as PriorSlice on the planar step (2 m, 0.5 rad: sigma_t = 0.2 m,
  // sigma_r = 0.2 * 0.5 + 0.05 * 2 = 0.2 rad); z, roll and pitch get the loose sigmas.
  PriorSlice slice2;
  PriorSlice3D slice3;
  slice3.mount = kBaseInCamera;
  setStepSigmas(slice2);
  slice2.configure();
  setStepSigmas(slice3);
  slice3.out_of_plane_sigma_translation = 0.5;
  slice3.out_of_plane_sigma_rotation = 0.25;
  slice3.configure();
  bindStep(slice2, se2(0, 0, 0), se2(0, 0, 0), se2(2.0, 0.0, 0.5));
  bindStep(slice3, Eigen::Isometry3d::Identity(), se2(0, 0, 0), se2(2.0, 0.0, 0.5));
  const Eigen::Matrix3d& i2 = slice2.information();
  const Eigen::Matrix<double, 6, 6>& i3 = slice3.information();
  EXPECT_NEAR(i3(0, 0), i2(0, 0), 1e-9);
  EXPECT_NEAR(i3(1, 1), i2(1, 1), 1e-9);
  EXPECT_NEAR(i3(5, 5), 4 * i2(2, 2), 1e-9);  // the error is q.vec: half the angle
  EXPECT_NEAR(i3(2, 2), 1 / (0.5 * 0.5), 1e-9);
  EXPECT_NEAR(i3(3, 3), 4 / (0.25 * 0.25), 1e-9);
  EXPECT_NEAR(i3(4, 4), 4 / (0.25 * 0.25), 1e-9);

  // In the camera frame: 5 cm along the optical axis (the base's forward) costs as much as in
  // 2D; 5 cm along the image's y (the base's up) only the loose sigma.
  const Eigen::Isometry3d forward = slice3.prior() * Eigen::Translation3d(0, 0, 0.05);
  const Eigen::Isometry3d up = slice3.prior() * Eigen::Translation3d(0, -0.05, 0);
  auto chi2 = [&](const Eigen::Isometry3d& t) {
    NormalEquations<Space3D> eq;
    slice3.linearize(t, eq);
    return eq.chi2;
  };
  EXPECT_NEAR(chi2(forward), 0.05 * 0.05 / (0.2 * 0.2), 1e-9);
  EXPECT_NEAR(chi2(up), 0.05 * 0.05 / (0.5 * 0.5), 1e-9);
}

// In a 3D tracker with the 3D wheel odometry as the motion model and the 3D prior as the only
// cue, the camera poses follow the odometry exactly (the prior takes the model's delta through
// the tracker's context and projects it back to the plane with its own mount).
TEST(PriorSlice3D, InATrackerTheCameraFollowsTheOdometry) {
  plugslam::MultiTracker<Space3D> tracker;
  auto model = std::make_shared<WheelOdometry3D>();
  model->mount = kBaseInCamera;
  tracker.motion.assign(model);
  auto aligner = std::make_shared<plugslam::MultiAligner<Space3D>>();
  auto slice = std::make_shared<PriorSlice3D>();
  slice->mount = kBaseInCamera;
  aligner->slices.assign(slice);
  aligner->min_inliers = 1;
  tracker.aligner.assign(aligner);
  for (auto* m : std::initializer_list<plugslam::Configurable*>{model.get(), slice.get(),
                                                                aligner.get(), &tracker})
    m->configure();
  const Eigen::Isometry2d start = se2(3.0, -2.0, 0.7);
  const Eigen::Isometry3d camera_in_base = baseInCamera().inverse();
  trackOdometry(
      tracker, start, se2(0.9, 0.02, 0.1), [&](const Eigen::Isometry2d& odom, const Frame& f) {
        const Eigen::Isometry3d expected = (Space2D::to3D(start) * camera_in_base).inverse() *
                                           Space2D::to3D(odom) * camera_in_base;
        expectPose(expected, f.estimate.in_map, 1e-9);
      });
  EXPECT_EQ(tracker.stats().aligned, 6u);
}

}  // namespace
