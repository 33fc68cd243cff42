// MotionPrediction without a motion model: constant velocity, its covariance bounded by the
// plausible accelerations and its typical error learned from the measured steps.
#include "plugslam/motion_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "plugslam/geometry.h"

using namespace plugslam;

namespace {

Frame at(double stamp) {
  Frame f;
  f.stamp = stamp;
  return f;
}

// Drives `steps` frames 3 s apart, each step 1 m forward with a gaussian error of `sigma` m
// along x (the log keeps a scan a metre), every step measured as `measured` says.
double drive(MotionPrediction<Space2D>& p, int steps, double sigma, bool measured,
             std::mt19937& rng, double& stamp, double interval = 3.0) {
  std::normal_distribution<double> noise(0.0, sigma);
  double last_sigma_x = 0;
  for (int i = 0; i < steps; ++i) {
    p.predict(nullptr, ConstantVelocityBounds{}, at(stamp));
    if (p.typical) last_sigma_x = std::sqrt((*p.typical)(0, 0));
    p.solved(se2(1.0 + noise(rng), 0, 0), measured);
    stamp += interval;
  }
  return last_sigma_x;
}

}  // namespace

// Seconds between scans let a robot change its velocity by metres, but one whose steps vary by
// 5 cm is predicted to about 5 cm: the typical error is learned; the bound stays as wide.
TEST(MotionPrediction, LearnsTheTypicalErrorOfConstantVelocity) {
  MotionPrediction<Space2D> p;
  std::mt19937 rng(4);
  double stamp = 0;
  const double sigma_x = drive(p, 60, 0.05, true, rng, stamp);
  EXPECT_GT(sigma_x, 0.03);
  EXPECT_LT(sigma_x, 0.1);
  const MotionEstimate<Space2D> e = p.predict(nullptr, ConstantVelocityBounds{}, at(stamp));
  ASSERT_TRUE(p.typical);
  EXPECT_GT(std::sqrt(e.covariance(0, 0)), 1.0);  // the accelerations' bound: metres
  EXPECT_NEAR(e.mean.translation().x(), 1.0, 0.1);
  // A gap of three intervals stretches the typical error as it does the bound.
  p.solved(se2(1, 0, 0), true);
  p.predict(nullptr, ConstantVelocityBounds{}, at(stamp + 3.0 + 9.0));
  ASSERT_TRUE(p.typical);
  EXPECT_GT(std::sqrt((*p.typical)(0, 0)), 2 * sigma_x);
}

// Steps the data did not fix (ambiguous, unchecked) may only repeat the prediction: they teach
// nothing, and before enough measured ones there is no typical error, only the bound.
TEST(MotionPrediction, LearnsOnlyFromMeasuredSteps) {
  MotionPrediction<Space2D> p;
  std::mt19937 rng(5);
  double stamp = 0;
  drive(p, 30, 0.05, false, rng, stamp);
  p.predict(nullptr, ConstantVelocityBounds{}, at(stamp));
  EXPECT_FALSE(p.typical);
  p.solved(se2(1, 0, 0), false);
  stamp += 3.0;
  // A reset forgets the velocity (the next prediction knows nothing) but not the typical error.
  drive(p, 10, 0.05, true, rng, stamp);
  p.reset();
  p.predict(nullptr, ConstantVelocityBounds{}, at(stamp));
  EXPECT_FALSE(p.typical);
  p.solved(se2(1, 0, 0), true);
  stamp += 3.0;
  p.predict(nullptr, ConstantVelocityBounds{}, at(stamp));
  EXPECT_TRUE(p.typical);
}

// Scans 0.1 s apart a metre each, varying by 30 cm: the accelerations bound the prediction to
// centimetres, and the typical error, however large the steps' spread, is never wider.
TEST(MotionPrediction, TheTypicalErrorStaysWithinTheBound) {
  MotionPrediction<Space2D> p;
  std::mt19937 rng(6);
  double stamp = 0;
  const ConstantVelocityBounds bounds;
  drive(p, 60, 0.3, true, rng, stamp, 0.1);
  const MotionEstimate<Space2D> e = p.predict(nullptr, bounds, at(stamp));
  EXPECT_LT(std::sqrt(e.covariance(0, 0)), 0.05);
  ASSERT_TRUE(p.typical);
  EXPECT_NEAR((*p.typical)(0, 0), e.covariance(0, 0), 1e-12);
}

// Frames 0.1 s and 1 m apart, then one 0.4 s later: the mean is one step (a logger that writes a
// frame when the robot moved), and through_gap the pace kept through the gap (a sensor that lost
// three frames), both in the robot's frame and, in the aligner's context, in the scene's. Only a
// gap has the second guess.
TEST(MotionPrediction, AGapInTheStampsIsPredictedBothWays) {
  const ConstantVelocityBounds bounds;
  MotionPrediction<Space2D> p;
  std::mt19937 rng(7);
  double stamp = 0;
  drive(p, 10, 0.0, true, rng, stamp, 0.1);
  EXPECT_FALSE(p.through_gap);
  const double gap = stamp + 0.3;
  const MotionEstimate<Space2D> e = p.predict(nullptr, bounds, at(gap));
  EXPECT_NEAR(e.mean.translation().x(), 1.0, 1e-9);
  ASSERT_TRUE(p.through_gap);
  EXPECT_NEAR(p.through_gap->translation().x(), 4.0, 1e-9);
  EXPECT_NEAR(p.through_gap->translation().y(), 0.0, 1e-9);
  const SE2 previous = se2(5, 2, 0.5);
  const AlignContext<Space2D> c = p.context(previous, previous * e.mean, e);
  ASSERT_TRUE(c.through_gap);
  EXPECT_TRUE(c.through_gap->isApprox(previous * *p.through_gap));
  p.solved(se2(4, 0, 0), true);
  EXPECT_FALSE(p.through_gap);
  p.predict(nullptr, bounds, at(gap + 0.1));
  EXPECT_FALSE(p.through_gap);
  EXPECT_FALSE(p.context(previous, previous, e).through_gap);
}
