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

void expectPose(const Eigen::Isometry2d& expected, const Eigen::Isometry2d& actual, double tol) {
  EXPECT_NEAR(expected.translation().x(), actual.translation().x(), tol);
  EXPECT_NEAR(expected.translation().y(), actual.translation().y(), tol);
  EXPECT_NEAR(0.0, plugslam::angleOf(expected.linear().transpose() * actual.linear()), tol);
}

TEST(WheelOdometry, DeltasComposeBackToTheOdometryPath) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Isometry2d> path{se2(2.0, -1.0, 0.3)};
  for (int i = 0; i < 50; ++i)
    path.push_back(path.back() * se2(0.3 * u(rng), 0.1 * u(rng), 0.4 * u(rng)));

  WheelOdometry model;
  model.configure();
  EXPECT_FALSE(model.predict(odomFrame(0, path[0])).has_value());  // nothing to be relative to
  Eigen::Isometry2d composed = path[0];
  for (size_t i = 1; i < path.size(); ++i) {
    if (i == 20) {
      // A frame without odometry predicts nothing; the next delta spans the gap.
      Frame empty;
      EXPECT_FALSE(model.predict(empty).has_value());
    }
    auto delta = model.predict(odomFrame(i, path[i]));
    ASSERT_TRUE(delta.has_value());
    composed = composed * delta->mean;
    expectPose(path[i], composed, 1e-9);
  }
  model.reset();
  EXPECT_FALSE(model.predict(odomFrame(99, path[3])).has_value());
}

TEST(WheelOdometry, ReadsTheConfiguredEntry) {
  WheelOdometry model;
  model.input = std::string("wheels");
  model.configure();
  EXPECT_FALSE(model.predict(odomFrame(0, se2(0, 0, 0), "wheels")).has_value());
  auto delta = model.predict(odomFrame(1, se2(1, 0, 0), "wheels"));
  ASSERT_TRUE(delta.has_value());
  expectPose(se2(1, 0, 0), delta->mean, 1e-12);
  EXPECT_FALSE(model.predict(odomFrame(2, se2(2, 0, 0), "odom")).has_value());
  model.input = std::string("");
  EXPECT_THROW(model.configure(), plugslam::ParamError);
}

// The covariance grows with the step the wheels measured (per metre and per radian, above the
// floors) and with the time between the frame and the reading it was given: a reading older
// than its frame did not see the motion since, which the recent speed bounds. A frame given the
// previous reading again predicts no motion, with the covariance of the motion it missed.
TEST(WheelOdometry, CovarianceGrowsWithTheStepAndWhatTheReadingsDidNotSee) {
  WheelOdometry model;
  model.configure();
  const auto sigmas = [](const plugslam::MotionEstimate<Space2D>& e) {
    return Eigen::Vector2d(std::sqrt(e.covariance(0, 0)), std::sqrt(e.covariance(2, 2)));
  };
  const auto at = [](double stamp, double reading, const Eigen::Isometry2d& pose) {
    Frame f;
    f.stamp = stamp;
    f.raw.set<Odometry2D>("odom", {reading, pose});
    return f;
  };
  ASSERT_FALSE(model.predict(at(0.0, 0.0, se2(0, 0, 0))));
  // 0.1 m straight, read at the frame: the floors.
  auto e = model.predict(at(0.1, 0.1, se2(0.1, 0, 0)));
  ASSERT_TRUE(e);
  EXPECT_NEAR(sigmas(*e).x(), model.min_sigma_translation(), 1e-12);
  EXPECT_NEAR(sigmas(*e).y(), model.min_sigma_rotation(), 1e-12);
  EXPECT_NEAR(e->covariance(0, 1), 0.0, 1e-15);
  // 2 m and 1 rad: the per-metre and per-radian terms.
  e = model.predict(at(0.2, 0.2, se2(0.1, 0, 0) * se2(2.0, 0, 1.0)));
  ASSERT_TRUE(e);
  EXPECT_NEAR(sigmas(*e).x(),
              model.sigma_translation_per_m() * 2.0 + model.sigma_translation_per_rad() * 1.0,
              1e-9);
  EXPECT_NEAR(sigmas(*e).y(),
              model.sigma_rotation_per_m() * 2.0 + model.sigma_rotation_per_rad() * 1.0, 1e-9);
  // The same reading again 0.5 s later: no motion predicted, and the covariance of what the
  // robot may have done since at its recent speed (2.1 m / 0.2 s over the readings kept).
  const Eigen::Isometry2d last = se2(0.1, 0, 0) * se2(2.0, 0, 1.0);
  e = model.predict(at(0.7, 0.2, last));
  ASSERT_TRUE(e);
  expectPose(se2(0, 0, 0), e->mean, 1e-12);
  const double speed = 2.1 / 0.2;
  EXPECT_NEAR(sigmas(*e).x(), model.min_sigma_translation() + speed * 0.5, 1e-9);
  // The next fresh reading's delta starts from that old one, so the missed time counts again, at
  // the speed over the readings kept then (2.2 m in 0.8 s).
  e = model.predict(at(0.8, 0.8, last * se2(0.1, 0, 0)));
  ASSERT_TRUE(e);
  EXPECT_NEAR(sigmas(*e).x(), model.min_sigma_translation() + 2.2 / 0.8 * 0.5, 1e-9);
}

TEST(PriorSlice, JacobianMatchesNumericalDifferentiation) {
  PriorSlice slice;
  slice.configure();
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(1.0, 2.0, 2.9), se2(0, 0, 0)};
  ASSERT_FALSE(slice.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx));
  ASSERT_TRUE(slice.bind(odomFrame(1, se2(0.7, 0.2, 0.6)), scene, ctx));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry2d t = slice.prior() * se2(0.5 * u(rng), 0.5 * u(rng), 2.5 * u(rng));
    Eigen::Matrix3d j;
    slice.error(t, &j);
    Eigen::Matrix3d numeric;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d dx = Eigen::Vector3d::Zero();
      dx[k] = h;
      const Eigen::Vector3d ep = slice.error(Space2D::boxplus(t, dx));
      const Eigen::Vector3d em = slice.error(Space2D::boxplus(t, -dx));
      numeric.col(k) = (ep - em) / (2 * h);
      numeric(2, k) = plugslam::normalizeAngle(ep[2] - em[2]) / (2 * h);
    }
    EXPECT_LT((numeric - j).cwiseAbs().maxCoeff(), 1e-6) << "trial " << trial << "\n"
                                                         << j << "\nvs\n"
                                                         << numeric;
  }
}

TEST(PriorSlice, ItsFactorPassesTheSdkJacobianCheck) {
  PriorSlice slice;
  slice.configure();
  bindStep(slice, se2(1.0, 2.0, 2.9), se2(0, 0, 0), se2(0.7, 0.2, 0.6));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Isometry2d t = slice.prior() * se2(0.5 * u(rng), 0.5 * u(rng), 2.5 * u(rng));
    const plugslam::SliceJacobianCheck r = plugslam::checkSliceJacobians(slice, t);
    EXPECT_EQ(r.factors, 1u);
    EXPECT_TRUE(r.ok()) << "trial " << trial << ": " << r;
  }
}

TEST(PriorSlice, AloneInAMultiAlignerReturnsThePriorExactly) {
  auto slice = std::make_shared<PriorSlice>();
  slice->configure();
  const Eigen::Isometry2d odom0 = se2(5.0, -3.0, 1.2), odom1 = odom0 * se2(0.8, 0.1, -0.7);
  AlignContext<Space2D> ctx{se2(-2.0, 4.0, -2.5), se2(-1.0, 3.0, 0.5)};
  const auto result = alignSecondReading(slice, odom0, odom1, ctx);
  expectPose(ctx.previous * odom0.inverse() * odom1, result.pose, 1e-9);
  expectExactPrior(result);
  EXPECT_TRUE(result.H.isApprox(slice->information(), 1e-9));
}

TEST(PriorSlice, NoiseModelScalesWithTheMotion) {
  PriorSlice slice;
  setStepSigmas(slice);
  slice.min_sigma_translation = 0.01;
  slice.min_sigma_rotation = 0.004;
  slice.configure();
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(0, 0, 0), se2(0, 0, 0)};
  slice.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx);

  // 2 m and 0.5 rad: sigma_t = 0.2 m, sigma_r = 0.2 * 0.5 + 0.05 * 2 = 0.2 rad.
  ASSERT_TRUE(slice.bind(odomFrame(1, se2(2.0, 0.0, 0.5)), scene, ctx));
  EXPECT_NEAR(slice.information()(0, 0), 1 / (0.2 * 0.2), 1e-9);
  EXPECT_NEAR(slice.information()(1, 1), 1 / (0.2 * 0.2), 1e-9);
  EXPECT_NEAR(slice.information()(2, 2), 1 / (0.2 * 0.2), 1e-9);
  EXPECT_EQ(slice.information()(0, 1), 0.0);

  // Standing still: the floors.
  ASSERT_TRUE(slice.bind(odomFrame(2, se2(2.0, 0.0, 0.5)), scene, ctx));
  EXPECT_NEAR(slice.information()(0, 0), 1 / (0.01 * 0.01), 1e-6);
  EXPECT_NEAR(slice.information()(2, 2), 1 / (0.004 * 0.004), 1e-6);

  // The factor's normal equations are J^T W J and J^T W e.
  NormalEquations<Space2D> eq;
  const Eigen::Isometry2d t = slice.prior() * se2(0.05, -0.02, 0.01);
  slice.linearize(t, eq);
  Eigen::Matrix3d j;
  const Eigen::Vector3d e = slice.error(t, &j);
  EXPECT_TRUE(eq.H.isApprox(j.transpose() * slice.information() * j, 1e-12));
  EXPECT_TRUE(eq.b.isApprox(j.transpose() * slice.information() * e, 1e-12));
  EXPECT_NEAR(eq.chi2, e.dot(slice.information() * e), 1e-9);
}

TEST(PriorSlice, RebindingTheSameFrameKeepsItsDelta) {
  PriorSlice slice;
  slice.configure();
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(1, 1, 0), se2(0, 0, 0)};
  slice.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx);
  ASSERT_TRUE(slice.bind(odomFrame(1, se2(1, 0, 0.1)), scene, ctx));
  const Eigen::Isometry2d first = slice.prior();
  ASSERT_TRUE(slice.bind(odomFrame(1, se2(1, 0, 0.1)), scene, ctx));
  expectPose(first, slice.prior(), 1e-12);
  // A frame without odometry adds nothing; the next delta spans the gap.
  Frame empty;
  empty.seq = 2;
  EXPECT_FALSE(slice.bind(empty, scene, ctx));
  ASSERT_TRUE(slice.bind(odomFrame(3, se2(2, 0, 0.1)), scene, ctx));
  expectPose(se2(1, 1, 0) * se2(1, 0, 0.1).inverse() * se2(2, 0, 0.1), slice.prior(), 1e-12);
}

TEST(PriorSlice, FramesWithoutSequenceNumbersAreToldApartByStamp) {
  PriorSlice slice;
  slice.configure();
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(0, 0, 0), se2(0, 0, 0)};
  Frame a = odomFrame(0, se2(0, 0, 0)), b = odomFrame(0, se2(1, 0, 0)),
        c = odomFrame(0, se2(3, 0, 0));
  a.stamp = 1.0;
  b.stamp = 2.0;
  c.stamp = 3.0;
  slice.bind(a, scene, ctx);
  ASSERT_TRUE(slice.bind(b, scene, ctx));
  expectPose(se2(1, 0, 0), slice.prior(), 1e-12);
  ASSERT_TRUE(slice.bind(c, scene, ctx));
  expectPose(se2(2, 0, 0), slice.prior(), 1e-12);
}

// Item 18.3: the odometry delta is computed once. In a tracker, the motion model measures it and
// the prior takes it from the AlignContext, but only when the model read the same entry.
TEST(PriorSlice, TakesTheMotionModelsDeltaWhenItReadTheSameEntry) {
  PropertyContainer scene;
  // The context's motion differs from the readings' delta, to tell which one the slice took.
  AlignContext<Space2D> ctx{se2(1.0, 1.0, 0.2), se2(0, 0, 0), se2(0.5, 0.0, 0.1)};
  ctx.motion_entry = "odom";
  {
    PriorSlice slice;
    slice.configure();
    // The first reading the slice sees adds no prior (as before the delta was shared).
    EXPECT_FALSE(slice.bind(odomFrame(0, se2(7, 7, 1)), scene, ctx));
    ASSERT_TRUE(slice.bind(odomFrame(1, se2(9, 7, 1)), scene, ctx));
    expectPose(se2(1.0, 1.0, 0.2) * se2(0.5, 0.0, 0.1), slice.prior(), 1e-12);
    // Without a motion, its own readings' delta.
    ctx.motion.reset();
    ASSERT_TRUE(slice.bind(odomFrame(2, se2(9, 8, 1)), scene, ctx));
    expectPose(se2(1.0, 1.0, 0.2) * se2(9, 7, 1).inverse() * se2(9, 8, 1), slice.prior(), 1e-12);
  }
  {
    PriorSlice slice;  // reads "wheels": the model's motion is not its odometry
    slice.input = std::string("wheels");
    slice.configure();
    ctx.motion = se2(0.5, 0.0, 0.1);
    EXPECT_FALSE(slice.bind(odomFrame(0, se2(0, 0, 0), "wheels"), scene, ctx));
    ASSERT_TRUE(slice.bind(odomFrame(1, se2(2, 0, 0), "wheels"), scene, ctx));
    expectPose(se2(1.0, 1.0, 0.2) * se2(2, 0, 0), slice.prior(), 1e-12);
  }
}

// The tracker's prediction names the one raw entry the wheel odometry read, so a PriorSlice
// reading that entry takes the model's delta (AlignContext::motion_entry); nothing without a
// reading.
TEST(WheelOdometry, ThePredictionNamesTheEntryItsDeltaCameFrom) {
  WheelOdometry model;
  model.input = std::string("wheels");
  model.configure();
  plugslam::MotionPrediction<Space2D> prediction;
  const plugslam::ConstantVelocityBounds bounds;
  prediction.predict(&model, bounds, odomFrame(0, se2(1, 0, 0), "wheels"));
  prediction.predict(&model, bounds, odomFrame(1, se2(2, 0, 0), "wheels"));
  ASSERT_TRUE(prediction.model_motion);
  expectPose(se2(1, 0, 0), prediction.model_motion->mean, 1e-12);
  EXPECT_EQ(prediction.model_entry, "wheels");
  prediction.predict(&model, bounds, odomFrame(2, se2(2, 0, 0), "other"));
  EXPECT_FALSE(prediction.model_motion);
  EXPECT_EQ(prediction.model_entry, "");
}

// In a tracker with wheel odometry as the motion model and the prior as the only cue, the poses
// follow the odometry exactly, with the tracker's context (motion and its entry) as the delta.
TEST(PriorSlice, InATrackerThePosesFollowTheOdometry) {
  plugslam::MultiTracker<Space2D> tracker;
  tracker.motion.assign(std::make_shared<WheelOdometry>());
  auto aligner = std::make_shared<plugslam::MultiAligner<Space2D>>();
  aligner->slices.assign(std::make_shared<PriorSlice>());
  aligner->min_inliers = 1;
  tracker.aligner.assign(aligner);
  for (auto* m : std::initializer_list<plugslam::Configurable*>{
           tracker.motion.get(), &aligner->slices[0], aligner.get(), &tracker})
    m->configure();
  const Eigen::Isometry2d start = se2(3.0, -2.0, 0.7);
  trackOdometry(tracker, start, se2(0.4, 0.05, 0.1),
                [&](const Eigen::Isometry2d& odom, const Frame& f) {
                  expectPose(start.inverse() * odom, Space2D::from3D(f.estimate.in_map), 1e-9);
                });
  // Frame 1 is the prior's first reading: no factor, the prediction stands (not aligned).
  EXPECT_EQ(tracker.stats().aligned, 6u);
}

}  // namespace

namespace {}  // namespace
