// The landmark cue without a good motion prior, on the simulator's street: the first step at
// highway speed (no velocity known yet), a wrong prediction held with confidence, and a gap in
// the frames. Each step must come out within 5 % of its length,
// or the frame must say that it could not be checked.
#include <gtest/gtest.h>

#include <initializer_list>
#include <memory>
#include <vector>

#include "landmark_tracker.h"
#include "plugslam/pipeline.h"
#include "rendered_frames.h"
#include "stereo_preprocessor.h"

namespace plugslam {
namespace {

using sim::sim3d::Simulator3D;

// 25 m/s at 10 Hz: 2.5 m between frames, the speed a highway's traffic keeps.
Simulator3D highway() {
  sim::sim3d::ScenarioOptions o;
  o.world = "street";
  o.rig = sim::sim3d::Rig::kStereo;
  o.speed = 25.0;
  return Simulator3D::fromOptions(o);
}

Frame preprocessed(const Simulator3D& sim, size_t k) {
  static visual::StereoPreprocessor pre;
  pre.configure();
  Frame frame = testing::renderedFrame(sim, k);
  EXPECT_TRUE(pre.process(frame));
  return frame;
}

// |estimated step - true step| / |true step| between two processed frames.
double stepError(const Frame& a, const Frame& b) {
  const Eigen::Vector3d truth = (a.raw.get<Eigen::Isometry3d>("ground_truth").inverse() *
                                 b.raw.get<Eigen::Isometry3d>("ground_truth"))
                                    .translation();
  const Eigen::Vector3d estimate = (a.estimate.world.inverse() * b.estimate.world).translation();
  return (estimate - truth).norm() / truth.norm();
}

// The stereo landmark tracker driven through some of a simulator's frames.
struct Drive {
  MultiTracker<Space3D> tracker;
  std::vector<Frame> frames;
  // Tracks frames `ks` of `sim`: each must come out valid and not lost, and checked when
  // `checked` says so.
  void run(const Simulator3D& sim, std::initializer_list<size_t> ks, bool checked) {
    testing::buildLandmarkTracker(tracker, 10.0);
    Pipeline pipeline;
    pipeline.tracker.assign(std::shared_ptr<Tracker>(std::shared_ptr<Tracker>(), &tracker));
    for (size_t k : ks) {
      frames.push_back(preprocessed(sim, k));
      pipeline.process(frames.back());
      ASSERT_TRUE(frames.back().estimate.valid);
      EXPECT_FALSE(frames.back().estimate.lost) << "frame " << k;
      if (checked) {
        EXPECT_FALSE(frames.back().estimate.unchecked) << "frame " << k;
      }
    }
  }
  // Every step within 5 % of its length, and no failure.
  void expectStepsWithinFivePercent() const {
    for (size_t i = 1; i < frames.size(); ++i)
      EXPECT_LT(stepError(frames[i - 1], frames[i]), 0.05) << "step into frame " << frames[i].seq;
    EXPECT_EQ(tracker.stats().failed, 0u);
  }
};

TEST(FastMotion, TheFirstHighwayStepIsRecovered) {
  // Before a step was seen the velocity is unknown: the prediction's covariance reaches
  // everywhere, and the frame is placed by descriptor matching without it, then refined.
  // Measured 0.5 % and 1.0 %; a solve stuck near zero motion (the old failure: far points agree
  // with standing still) is off by most of the 2.5 m.
  Drive d;
  d.run(highway(), {0, 1, 2}, true);
  d.expectStepsWithinFivePercent();
}

TEST(FastMotion, AConfidentWrongPredictionIsCaught) {
  // The prediction says "standing still, to 2 cm": the landmarks' windows are a few pixels
  // wide, so near points, which moved tens of pixels, never pair, while far ones do and agree
  // with standing still. Without the check the solve converges there, valid and wrong.
  const Simulator3D sim = highway();
  MultiTracker<Space3D> tracker;
  testing::buildLandmarkTracker(tracker, 10.0);
  Frame first = preprocessed(sim, 0);
  const TrackEvents events = tracker.track(first);
  ASSERT_TRUE(events.started);
  const PropertyContainer& scene = events.started->scene;
  Frame second = preprocessed(sim, 1);
  const double step = (first.raw.get<Eigen::Isometry3d>("ground_truth").inverse() *
                       second.raw.get<Eigen::Isometry3d>("ground_truth"))
                          .translation()
                          .norm();
  AlignContext<Space3D> context(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity());
  context.covariance =
      MotionEstimate<Space3D>::isotropic(Eigen::Isometry3d::Identity(), 0.02, 0.005).covariance;
  const auto truth = [&] {
    return first.raw.get<Eigen::Isometry3d>("ground_truth").inverse() *
           second.raw.get<Eigen::Isometry3d>("ground_truth");
  };
  MultiAligner<Space3D>& aligner = *tracker.aligner;
  aligner.relocalise.set(false);
  const AlignResult<Space3D> trusted = aligner.align(second, scene, context);
  aligner.relocalise.set(true);
  const AlignResult<Space3D> checked = aligner.align(second, scene, context);
  const double trusted_error = (trusted.pose.translation() - truth().translation()).norm();
  const double checked_error = (checked.pose.translation() - truth().translation()).norm();
  // The trap is real: trusted, the solve is valid (or fails), never right.
  if (trusted.valid) {
    EXPECT_GT(trusted_error, 0.05 * step) << "the confident prediction no longer misleads";
  }
  // Checked, the hypothesis made without the prediction explains more and wins. Measured:
  // trusted 2.39 m off of 2.5 m, checked 0.013 m.
  ASSERT_TRUE(checked.valid);
  EXPECT_TRUE(checked.hypothesis);
  EXPECT_FALSE(checked.unchecked);
  EXPECT_LT(checked_error, 0.05 * step) << "trusted error " << trusted_error << " m";
}

TEST(FastMotion, AFrameGapIsBridgedWithoutThePrediction) {
  // Half a second of frames is lost at 8 m/s: the constant-velocity prediction is one step
  // (0.8 m) where the car went 4 m, and its covariance, grown with the gap, spreads the
  // landmarks' windows too wide to search: the frame after the gap is placed by descriptor
  // matching and RANSAC, then refined.
  sim::sim3d::ScenarioOptions o;
  o.world = "street";
  o.rig = sim::sim3d::Rig::kStereo;
  // Measured: 0.5-1.2 % per step, 0.5 % over the gap.
  Drive d;
  d.run(Simulator3D::fromOptions(o), {0, 1, 2, 3, 8, 9, 10}, true);
  d.expectStepsWithinFivePercent();
  EXPECT_GE(d.tracker.stats().hypotheses, 1u) << "the step over the gap";
}

TEST(FastMotion, ThreeFramesLostAtSpeedAreBridgedByThePaceKept) {
  // Three frames lost at 25 m/s: 10 m between two frames, the prediction's mean one step (as if a
  // logger had written a frame when the car had moved) and the pace kept through the gap the
  // other guess. Few of the young local map's landmarks match by descriptor so far ahead, so
  // recovery without the prediction cannot place the frame; the pace kept can.
  // Without it: 14 % over the gap.
  Drive d;
  d.run(highway(), {0, 1, 2, 3, 4, 5, 9, 10, 11}, false);
  d.expectStepsWithinFivePercent();
}

}  // namespace
}  // namespace plugslam
