#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/multi_tracker.h"
#include "plugslam/slice_check.h"
#include "prior_slice.h"
#include "wheel_odometry.h"

using plugslam::AlignContext;
using plugslam::Frame;
using plugslam::NormalEquations;
using plugslam::Odometry2D;
using plugslam::PropertyContainer;
using plugslam::se2;
using plugslam::Space2D;
using plugslam::odometry::PriorSlice;
using plugslam::odometry::WheelOdometry;

namespace {

Frame odomFrame(uint64_t seq, const Eigen::Isometry2d& pose, const std::string& entry = "odom") {
  Frame f;
  f.seq = seq;
  f.stamp = 0.1 * seq;
  f.raw.set<Odometry2D>(entry, {f.stamp, pose});
  return f;
}

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
    composed = composed * *delta;
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
  expectPose(se2(1, 0, 0), *delta, 1e-12);
  EXPECT_FALSE(model.predict(odomFrame(2, se2(2, 0, 0), "odom")).has_value());
  model.input = std::string("");
  EXPECT_THROW(model.configure(), plugslam::ParamError);
}

// Odometry arriving less often than the scans: a frame between two readings gets the last one,
// stamped with its own (older) time. The model carries it to the frame's time with the recent
// velocity, so each frame's delta is the motion of its own interval, not zero then five at once;
// and the deltas still compose to the readings wherever a fresh one arrives.
TEST(WheelOdometry, AStaleReadingIsExtrapolatedWithTheRecentVelocity) {
  // 0.5 m/s forward, turning 0.3 rad/s; frames every 0.2 s, readings at every 5th frame after 10.
  const auto truth = [](double t) {
    const double w = 0.3, v = 0.5;
    return se2(v / w * std::sin(w * t), v / w * (1 - std::cos(w * t)), w * t);
  };
  const auto frameAt = [&](uint64_t seq) {
    Frame f;
    f.seq = seq;
    f.stamp = 0.2 * static_cast<double>(seq);
    const uint64_t read = seq < 10 ? seq : seq - seq % 5;  // the last reading's frame
    const double t = 0.2 * static_cast<double>(read);
    f.raw.set<Odometry2D>("odom", {t, truth(t)});
    return f;
  };
  WheelOdometry model, stale;
  model.configure();
  stale.max_extrapolation = 0.0;  // the reading taken as the pose at the frame
  stale.configure();
  model.predict(frameAt(0));
  stale.predict(frameAt(0));
  Eigen::Isometry2d composed = truth(0);
  double worst = 0, worst_stale = 0;
  for (uint64_t i = 1; i < 40; ++i) {
    const Frame f = frameAt(i);
    const auto delta = model.predict(f);
    const auto delta_stale = stale.predict(f);
    ASSERT_TRUE(delta && delta_stale);
    const Eigen::Isometry2d step = truth(f.stamp - 0.2).inverse() * truth(f.stamp);
    worst = std::max(worst, (step.inverse() * *delta).translation().norm());
    worst_stale = std::max(worst_stale, (step.inverse() * *delta_stale).translation().norm());
    composed = composed * *delta;
    if (i % 5 == 0) expectPose(truth(f.stamp), composed, 1e-9);  // fresh: back on the readings
    // What was not measured is said (the tracker's gate and the prior widen by it): the
    // extrapolation this delta ends with and the one it starts from (0.1 m per frame carried).
    const double carried = i > 10 ? 0.1 * static_cast<double>(i % 5) : 0.0;
    const double before = i > 11 ? 0.1 * static_cast<double>((i - 1) % 5) : 0.0;
    EXPECT_EQ(model.extrapolated().has_value(), carried + before > 0) << i;
    EXPECT_FALSE(stale.extrapolated().has_value());
    if (model.extrapolated()) {
      EXPECT_NEAR(model.extrapolated()->translation().norm(), carried + before, 0.01) << i;
    }
  }
  // The true step is 0.1 m: the extrapolation is off by the turn's curvature only (1.2 cm);
  // the stale reading predicts no motion (0.1 m off) and then five steps at once (0.4 m off).
  EXPECT_LT(worst, 0.02);
  EXPECT_GT(worst_stale, 0.35);
}

// A new reading older than its frame measured the step only up to its stamp. The prediction stays
// the readings' own delta (CARMEN stamps are too loose to carry it on), but the part after the
// reading is said (the recent velocity over the reading's age), so the tracker's gate and the
// prior widen by it and the seeder may check the frame (issue 20). The next frame's delta starts
// from that reading, so it holds the same part again (the frame's alignment took it up): that
// frame says it too.
TEST(WheelOdometry, ANewReadingOlderThanItsFrameSaysWhatItDidNotSee) {
  WheelOdometry model;
  model.configure();
  // 0.5 m/s straight; frames every 0.2 s, each with a reading taken 0.1 s before it.
  for (uint64_t i = 0; i < 10; ++i) {
    Frame f;
    f.seq = i;
    f.stamp = 0.2 * static_cast<double>(i);
    const double t = f.stamp - 0.1;
    f.raw.set<Odometry2D>("odom", {t, se2(0.5 * t, 0, 0)});
    const auto delta = model.predict(f);
    if (i == 0) continue;
    ASSERT_TRUE(delta.has_value()) << i;
    expectPose(se2(0.1, 0, 0), *delta, 1e-12);  // reading to reading, not carried
    ASSERT_TRUE(model.extrapolated().has_value()) << i;
    // Its own 0.05 m after the reading, and from frame 2 on the previous frame's 0.05 m.
    EXPECT_NEAR(model.extrapolated()->translation().norm(), i == 1 ? 0.05 : 0.10, 1e-9) << i;
  }
  // A reading stamped at its frame saw all of this frame's step, but the delta still starts from
  // the previous frame's older reading.
  Frame fresh;
  fresh.seq = 10;
  fresh.stamp = 2.0;
  fresh.raw.set<Odometry2D>("odom", {2.0, se2(1.0, 0, 0)});
  ASSERT_TRUE(model.predict(fresh).has_value());
  ASSERT_TRUE(model.extrapolated().has_value());
  EXPECT_NEAR(model.extrapolated()->translation().norm(), 0.05, 1e-9);
  // The next one, from a reading at its frame to a reading at its frame, saw all of it.
  Frame next;
  next.seq = 11;
  next.stamp = 2.2;
  next.raw.set<Odometry2D>("odom", {2.2, se2(1.1, 0, 0)});
  ASSERT_TRUE(model.predict(next).has_value());
  EXPECT_FALSE(model.extrapolated().has_value());
}

// The extrapolation never carries more motion than the readings measured: a reading older than
// the history behind it is carried by at most that history's motion, and max_extrapolation caps
// the age.
TEST(WheelOdometry, ExtrapolationIsBoundedByTheMeasuredMotionAndItsLimit) {
  WheelOdometry model;
  model.max_extrapolation = 2.0;
  model.configure();
  Frame a, b, c;
  a.seq = 0, a.stamp = 0.0, a.raw.set<Odometry2D>("odom", {0.0, se2(0, 0, 0)});
  b.seq = 1, b.stamp = 0.5, b.raw.set<Odometry2D>("odom", {0.5, se2(0.25, 0, 0)});
  c.seq = 2, c.stamp = 10.0, c.raw.set<Odometry2D>("odom", {0.5, se2(0.25, 0, 0)});
  model.predict(a);
  model.predict(b);
  const auto delta = model.predict(c);  // 9.5 s old, 0.5 s of readings behind it
  ASSERT_TRUE(delta.has_value());
  expectPose(se2(0.25, 0, 0), *delta, 1e-12);
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
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(1.0, 2.0, 2.9), se2(0, 0, 0)};
  slice.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx);
  ASSERT_TRUE(slice.bind(odomFrame(1, se2(0.7, 0.2, 0.6)), scene, ctx));
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
  plugslam::MultiAligner<Space2D> aligner;
  aligner.slices.assign(slice);
  aligner.min_inliers = 1;
  PropertyContainer scene;
  const Eigen::Isometry2d odom0 = se2(5.0, -3.0, 1.2), odom1 = odom0 * se2(0.8, 0.1, -0.7);
  AlignContext<Space2D> ctx{se2(-2.0, 4.0, -2.5), se2(-1.0, 3.0, 0.5)};

  auto first = aligner.align(odomFrame(0, odom0), scene, ctx);
  EXPECT_EQ(first.factors, 0u);  // the first reading has no delta yet

  auto result = aligner.align(odomFrame(1, odom1), scene, ctx);
  const Eigen::Isometry2d z = ctx.previous * odom0.inverse() * odom1;
  expectPose(z, result.pose, 1e-9);
  EXPECT_TRUE(result.valid);
  EXPECT_EQ(result.factors, 1u);
  EXPECT_LT(result.chi2, 1e-12);
  EXPECT_TRUE(result.H.isApprox(slice->information(), 1e-9));
}

TEST(PriorSlice, NoiseModelScalesWithTheMotion) {
  PriorSlice slice;
  slice.sigma_translation_per_m = 0.1;
  slice.sigma_rotation_per_rad = 0.2;
  slice.sigma_rotation_per_m = 0.05;
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

// The part of the model's delta it extrapolated (a reading older than the frame) was not
// measured: the prior's sigmas grow by its size (translation and turn), so the prior does not
// hold the solve on a guess.
TEST(PriorSlice, AnExtrapolatedDeltaWeighsLess) {
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(0, 0, 0), se2(0, 0, 0), se2(0.5, 0.0, 0.1)};
  ctx.motion_entry = "odom";
  PriorSlice measured, extrapolated;
  for (PriorSlice* s : {&measured, &extrapolated}) {
    s->sigma_translation_per_m = 0.02;
    s->min_sigma_translation = 0.02;
    s->sigma_rotation_per_rad = 0.2;
    s->min_sigma_rotation = 0.05;
    s->configure();
  }
  EXPECT_FALSE(measured.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx));
  ASSERT_TRUE(measured.bind(odomFrame(1, se2(0.5, 0, 0.1)), scene, ctx));
  ctx.motion_extrapolated = se2(0.3, 0.0, 0.05);
  EXPECT_FALSE(extrapolated.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx));
  ASSERT_TRUE(extrapolated.bind(odomFrame(1, se2(0.5, 0, 0.1)), scene, ctx));
  expectPose(measured.prior(), extrapolated.prior(), 1e-12);  // the same delta
  // sigma_t 0.02 -> 0.02 + 0.3, sigma_r max(0.05, 0.2 * 0.1 + 0.02 * 0.5) = 0.05 -> 0.1.
  EXPECT_NEAR(measured.information()(0, 0), 1 / (0.02 * 0.02), 1e-6);
  EXPECT_NEAR(extrapolated.information()(0, 0), 1 / (0.32 * 0.32), 1e-6);
  EXPECT_NEAR(measured.information()(2, 2), 1 / (0.05 * 0.05), 1e-6);
  EXPECT_NEAR(extrapolated.information()(2, 2), 1 / (0.1 * 0.1), 1e-6);
}

// The tracker's prediction names the one raw entry the wheel odometry read, so a PriorSlice
// reading that entry takes the model's delta (AlignContext::motion_entry); nothing without a
// reading.
TEST(WheelOdometry, ThePredictionNamesTheEntryItsDeltaCameFrom) {
  WheelOdometry model;
  model.input = std::string("wheels");
  model.configure();
  plugslam::MotionPrediction<Space2D> prediction;
  prediction.predict(&model, false, odomFrame(0, se2(1, 0, 0), "wheels"), se2(0, 0, 0));
  prediction.predict(&model, false, odomFrame(1, se2(2, 0, 0), "wheels"), se2(0, 0, 0));
  ASSERT_TRUE(prediction.model_motion);
  expectPose(se2(1, 0, 0), *prediction.model_motion, 1e-12);
  EXPECT_EQ(prediction.model_entry, "wheels");
  prediction.predict(&model, false, odomFrame(2, se2(2, 0, 0), "other"), se2(0, 0, 0));
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
  Eigen::Isometry2d odom = start;
  for (uint64_t i = 0; i < 8; ++i) {
    if (i > 0) odom = odom * se2(0.4, 0.05, 0.1);
    Frame f = odomFrame(i, odom);
    tracker.track(f);
    ASSERT_TRUE(f.estimate.valid);
    // One local map (no splitter), started at the first frame: its frame is the run's.
    ASSERT_EQ(f.estimate.local_map, 0);
    expectPose(start.inverse() * odom, Space2D::from3D(f.estimate.in_map), 1e-9);
  }
  // Frame 1 is the prior's first reading: no factor, the prediction stands (not aligned).
  EXPECT_EQ(tracker.stats().aligned, 6u);
}

}  // namespace

namespace {

TEST(PriorSlice, ObservedDisagreementWeighsTheOdometryDown) {
  // Issue 20: 1 m steps straight ahead, model sigmas 0.05 m (0.05 per m) and 0.02 rad (0.02 per
  // m). One frame whose solved motion was 0.5 m longer than the odometry said (a slip) is a
  // residual of 10 sigmas: the running mean of squares over 10 frames becomes 0.1 x 100 = 10,
  // so the next prior's translation sigma grows by sqrt(10); its rotation is untouched. It fades
  // as 0.9^k: after 25 agreeing frames the mean is 0.72 and the model's sigma is back.
  PriorSlice slice;
  slice.disagreement_frames = 10;
  slice.configure();
  PropertyContainer scene;
  AlignContext<Space2D> ctx{se2(0, 0, 0), se2(0, 0, 0)};
  slice.bind(odomFrame(0, se2(0, 0, 0)), scene, ctx);
  ASSERT_TRUE(slice.bind(odomFrame(1, se2(1, 0, 0)), scene, ctx));
  EXPECT_NEAR(slice.information()(0, 0), 1 / (0.05 * 0.05), 1e-9);

  ctx.motion_residual = se2(0.5, 0, 0);
  ASSERT_TRUE(slice.bind(odomFrame(2, se2(2, 0, 0)), scene, ctx));
  EXPECT_NEAR(slice.disagreementScale().x(), std::sqrt(10.0), 1e-9);
  EXPECT_NEAR(slice.disagreementScale().y(), 1.0, 1e-12);
  EXPECT_NEAR(slice.information()(0, 0), 1 / (10.0 * 0.05 * 0.05), 1e-9);
  EXPECT_NEAR(slice.information()(2, 2), 1 / (0.02 * 0.02), 1e-9);
  // Rebinding the same frame (the aligner's recovery does) does not count the residual twice.
  ASSERT_TRUE(slice.bind(odomFrame(2, se2(2, 0, 0)), scene, ctx));
  EXPECT_NEAR(slice.disagreementScale().x(), std::sqrt(10.0), 1e-9);

  ctx.motion_residual = se2(0, 0, 0);
  for (uint64_t k = 3; k < 28; ++k)
    ASSERT_TRUE(slice.bind(odomFrame(k, se2(static_cast<double>(k), 0, 0)), scene, ctx));
  EXPECT_DOUBLE_EQ(slice.disagreementScale().x(), 1.0);
  EXPECT_NEAR(slice.information()(0, 0), 1 / (0.05 * 0.05), 1e-9);

  // Off: the model's sigmas whatever the residual.
  slice.disagreement_frames = 0;
  ctx.motion_residual = se2(5, 0, 1);
  ASSERT_TRUE(slice.bind(odomFrame(28, se2(28, 0, 0)), scene, ctx));
  EXPECT_NEAR(slice.information()(0, 0), 1 / (0.05 * 0.05), 1e-9);
}

}  // namespace

// Wheels 10 % short, a wheel base 5 % off and a heading drift of 5 deg per metre (issue 20's
// degraded odometry): fed the motions the tracker solved, the model learns all three and its
// deltas come back to the true steps; a slip among them teaches nothing.
TEST(WheelOdometry, CalibratesScaleWheelBaseAndHeadingDriftFromTheSolvedMotion) {
  const double scale = 0.9, rotation_scale = 1.05, drift = 5.0 * M_PI / 180;  // per metre
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> forward(0.05, 0.5), turn(-0.4, 0.4);
  std::normal_distribution<double> noise(0.0, 0.005);
  WheelOdometry model;
  model.calibration_distance = 50.0;
  model.configure();
  Eigen::Isometry2d odom = Eigen::Isometry2d::Identity();
  model.predict(odomFrame(0, odom));
  double driven = 0;
  Eigen::Vector3d last_error = Eigen::Vector3d::Zero();
  for (uint64_t i = 1; driven < 120.0; ++i) {
    const Eigen::Vector3d truth(forward(rng), 0.02 * turn(rng), turn(rng));
    // What the miscalibrated wheels read for that step.
    const Eigen::Vector3d read(truth.x() * scale, truth.y() * scale,
                               (truth.z() + drift * truth.x()) * rotation_scale);
    odom = odom * se2(read);
    auto delta = model.predict(odomFrame(i, odom));
    ASSERT_TRUE(delta.has_value());
    last_error = plugslam::toVector(se2(truth).inverse() * *delta);
    Eigen::Vector3d solved = truth + Eigen::Vector3d(noise(rng), noise(rng), 0.2 * noise(rng));
    if (i == 40) solved.x() += 0.8;  // a slip: the wheels turned, the robot did not follow
    model.solved(se2(solved));
    driven += truth.x();
  }
  const auto& c = model.calibration();
  EXPECT_NEAR(c.scale(), 1 / scale, 0.01);
  EXPECT_NEAR(c.rotationScale(), 1 / rotation_scale, 0.01);
  EXPECT_NEAR(c.headingPerMetre(), -drift / scale, 0.005);
  EXPECT_LT(last_error.head<2>().norm(), 0.01);
  EXPECT_LT(std::abs(last_error.z()), 0.005);

  // Without calibration_distance the deltas are the readings'.
  WheelOdometry plain;
  plain.configure();
  plain.predict(odomFrame(0, Eigen::Isometry2d::Identity()));
  auto d = plain.predict(odomFrame(1, se2(0.3, 0.0, 0.1)));
  plain.solved(se2(0.5, 0.0, 0.3));
  d = plain.predict(odomFrame(2, se2(0.3, 0.0, 0.1) * se2(0.3, 0.0, 0.1)));
  ASSERT_TRUE(d.has_value());
  expectPose(se2(0.3, 0.0, 0.1), *d, 1e-12);
}
