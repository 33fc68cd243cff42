#pragma once
// What both odometry tests feed their modules (one wheel-odometry reading a frame, 10 Hz
// stamps), and how they check a prior slice alone in a Multi-Aligner.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>

#include "plugslam/frame.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/sensor_data.h"

namespace odometry_test {

/// Frame `seq`, stamped 0.1 s * seq, with the odometry reading `pose` under `entry`.
inline plugslam::Frame odomFrame(uint64_t seq, const Eigen::Isometry2d& pose,
                                 const std::string& entry = "odom") {
  plugslam::Frame f;
  f.seq = seq;
  f.stamp = 0.1 * seq;
  f.raw.set<plugslam::Odometry2D>(entry, {f.stamp, pose});
  return f;
}

/// Binds `slice` to the odometry step from reading a (frame 0) to reading b (frame 1), the robot
/// at `previous`.
template <class Slice, class Pose>
void bindStep(Slice& slice, const Pose& previous, const Eigen::Isometry2d& a,
              const Eigen::Isometry2d& b) {
  plugslam::PropertyContainer scene;
  const plugslam::AlignContext<typename Slice::Factor::Space> ctx{previous, previous};
  slice.bind(odomFrame(0, a), scene, ctx);
  ASSERT_TRUE(slice.bind(odomFrame(1, b), scene, ctx));
}

/// The step noise model the 2D and 3D prior slices are compared with: 0.1 m per metre, 0.2 rad
/// per radian and 0.05 rad per metre.
template <class Slice>
void setStepSigmas(Slice& slice) {
  slice.sigma_translation_per_m = 0.1;
  slice.sigma_rotation_per_rad = 0.2;
  slice.sigma_rotation_per_m = 0.05;
}

/// Tracks 8 frames of odometry from `start`, `step` apart, each of which must stay in the first
/// local map (the tracker has no splitter, and its frame is the run's); `check(odom, frame)`
/// checks each frame's estimate against its odometry reading.
template <class Tracker, class Check>
void trackOdometry(Tracker& tracker, const Eigen::Isometry2d& start, const Eigen::Isometry2d& step,
                   const Check& check) {
  Eigen::Isometry2d odom = start;
  for (uint64_t i = 0; i < 8; ++i) {
    if (i > 0) odom = odom * step;
    plugslam::Frame f = odomFrame(i, odom);
    tracker.track(f);
    ASSERT_TRUE(f.estimate.valid) << i;
    ASSERT_EQ(f.estimate.local_map, 0) << i;
    check(odom, f);
  }
}

/// What a Multi-Aligner with `slice` alone returns for the second of two frames with the
/// odometry readings odom0 and odom1 (the first has no delta yet, so no factor).
template <class S, class Slice>
plugslam::AlignResult<S> alignSecondReading(const std::shared_ptr<Slice>& slice,
                                            const Eigen::Isometry2d& odom0,
                                            const Eigen::Isometry2d& odom1,
                                            const plugslam::AlignContext<S>& ctx) {
  plugslam::MultiAligner<S> aligner;
  aligner.slices.assign(slice);
  aligner.min_inliers = 1;
  plugslam::PropertyContainer scene;
  EXPECT_EQ(aligner.align(odomFrame(0, odom0), scene, ctx).factors, 0u);
  return aligner.align(odomFrame(1, odom1), scene, ctx);
}

/// A prior slice's result when it is the only cue: valid, one factor, met exactly.
template <class S>
void expectExactPrior(const plugslam::AlignResult<S>& result) {
  EXPECT_TRUE(result.valid);
  EXPECT_EQ(result.factors, 1u);
  EXPECT_LT(result.chi2, 1e-12);
}

}  // namespace odometry_test
