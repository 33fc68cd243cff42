#include "plugslam/eval/rpe.h"

#include <gtest/gtest.h>

#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace {

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, 0.0);
  return p;
}

// Reference: 1 m steps along x every 0.5 s. Estimate: odometry that over-reads distance by 10 %.
struct Drift {
  Trajectory ref, est;
  Drift() {
    for (int i = 0; i <= 10; ++i) {
      ref.push_back(0.5 * i, planar(i, 0, 0));
      est.push_back(0.5 * i, planar(1.1 * i, 0, 0));
    }
  }
};

TEST(RpeTest, ScaleDriftByFrames) {
  Drift d;
  RpeOptions o;
  o.delta = 1;
  RpeResult r = computeRpe(d.ref, d.est, o);
  EXPECT_EQ(r.pairs, 10u);
  EXPECT_NEAR(r.translation.mean, 0.1, 1e-12);
  EXPECT_NEAR(r.translation.rmse, 0.1, 1e-12);
  EXPECT_NEAR(r.translation.std, 0.0, 1e-12);
  EXPECT_NEAR(r.rotation_deg.max, 0.0, 1e-12);
  o.delta = 2;
  r = computeRpe(d.ref, d.est, o);
  EXPECT_EQ(r.pairs, 9u);
  EXPECT_NEAR(r.translation.median, 0.2, 1e-12);
  o.all_pairs = false;
  EXPECT_EQ(computeRpe(d.ref, d.est, o).pairs, 5u);
}

TEST(RpeTest, SegmentsListEveryMeasuredPairInOrder) {
  Drift d;
  RpeOptions o;
  o.delta = 2;
  const RpeResult r = computeRpe(d.ref, d.est, o);
  ASSERT_EQ(r.segments.size(), r.pairs);
  for (size_t k = 0; k < r.segments.size(); ++k) {
    const RpeSegment& s = r.segments[k];
    EXPECT_EQ(s.first.ref, k);
    EXPECT_EQ(s.last.ref, k + 2);
    EXPECT_NEAR(s.translation, 0.2, 1e-12);  // 10 % over-read of 2 m
    EXPECT_NEAR(s.length_m, 2.0, 1e-12);
    EXPECT_NEAR(s.rotation_deg, 0.0, 1e-12);
  }
}

TEST(RpeTest, ScaleDriftByDistanceAndTime) {
  Drift d;
  RpeOptions o;
  o.unit = RpeUnit::Meters;
  o.delta = 3.0;  // three 1 m steps of the reference
  RpeResult r = computeRpe(d.ref, d.est, o);
  EXPECT_EQ(r.pairs, 8u);
  EXPECT_NEAR(r.translation.max, 0.3, 1e-12);
  EXPECT_NEAR(r.translation.min, 0.3, 1e-12);
  // 10 % scale drift is 10 % of every segment's 3 m, whatever its start.
  EXPECT_EQ(r.translation_percent.count, 8u);
  EXPECT_NEAR(r.translation_percent.mean, 10.0, 1e-9);
  EXPECT_NEAR(r.translation_percent.max, 10.0, 1e-9);
  EXPECT_NEAR(r.length_m.mean, 3.0, 1e-12);
  // A segment is the first pose at least delta further: 2.5 m asks for 3 m segments.
  o.delta = 2.5;
  r = computeRpe(d.ref, d.est, o);
  EXPECT_NEAR(r.length_m.min, 3.0, 1e-12);
  EXPECT_NEAR(r.translation_percent.mean, 10.0, 1e-9);
  o.unit = RpeUnit::Seconds;
  o.delta = 1.0;  // two 0.5 s steps
  r = computeRpe(d.ref, d.est, o);
  EXPECT_EQ(r.pairs, 9u);
  EXPECT_NEAR(r.translation.mean, 0.2, 1e-12);
  EXPECT_NEAR(r.translation_percent.mean, 10.0, 1e-9);
}

TEST(RpeTest, PercentLeavesOutSegmentsWithoutTravel) {
  // The robot stands still for two frames: those one-frame segments have no path length and
  // no percentage, but still count in the metric errors.
  Trajectory ref, est;
  const double xs[] = {0, 1, 1, 1, 2};
  for (int i = 0; i < 5; ++i) {
    ref.push_back(i, planar(xs[i], 0, 0));
    est.push_back(i, planar(1.2 * xs[i], 0, 0));
  }
  const RpeResult r = computeRpe(ref, est, RpeOptions{});
  EXPECT_EQ(r.pairs, 4u);
  EXPECT_EQ(r.translation_percent.count, 2u);
  EXPECT_NEAR(r.translation_percent.mean, 20.0, 1e-9);
  EXPECT_NEAR(r.length_m.min, 0.0, 1e-12);
}

TEST(RpeTest, HeadingDrift) {
  // The estimate turns 1 deg more per step than the reference (both drive straight in their
  // own frame): each one-step segment is off by 1 deg and by the chord it bends.
  Trajectory ref, est;
  const double step = M_PI / 180.0;
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int i = 0; i <= 20; ++i) {
    ref.push_back(i, planar(i, 0, 0));
    est.push_back(i, p);
    p = p * planar(1.0, 0.0, step);
  }
  const RpeResult r = computeRpe(ref, est, RpeOptions{});
  EXPECT_NEAR(r.rotation_deg.mean, 1.0, 1e-9);
  EXPECT_NEAR(r.rotation_deg.std, 0.0, 1e-9);
  EXPECT_NEAR(r.translation.mean, 0.0, 1e-9);  // the step itself is exact, only heading drifts
  RpeOptions two;
  two.delta = 2;
  const RpeResult r2 = computeRpe(ref, est, two);
  EXPECT_NEAR(r2.rotation_deg.mean, 2.0, 1e-9);
  // Over two steps the second metre is driven 1 deg off: the end is off by |(cos 1deg - 1, sin
  // 1deg)| = 2 sin(0.5 deg).
  EXPECT_NEAR(r2.translation.mean, 2.0 * std::sin(step / 2), 1e-12);
}

TEST(RpeTest, RejectsBadDeltaAndTooShortTrajectories) {
  Drift d;
  RpeOptions o;
  o.delta = 0.5;
  EXPECT_THROW(computeRpe(d.ref, d.est, o), InputError);  // fractional frames
  o.delta = -1;
  EXPECT_THROW(computeRpe(d.ref, d.est, o), InputError);
  o.delta = 11;
  EXPECT_THROW(computeRpe(d.ref, d.est, o), InputError);  // longer than the trajectory
  o.unit = RpeUnit::Meters;
  o.delta = 50.0;
  EXPECT_THROW(computeRpe(d.ref, d.est, o), InputError);
  EXPECT_EQ(parseRpeUnit("m"), RpeUnit::Meters);
  EXPECT_THROW(parseRpeUnit("km"), InputError);
}

}  // namespace
}  // namespace plugslam
