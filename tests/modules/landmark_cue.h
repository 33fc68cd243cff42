#pragma once
// A minimal synthetic cue for testing the generic core modules without any sensor plugin:
// landmarks with known identities. The measurement and the scene hold a
// std::vector<Eigen::Vector2d> indexed by landmark id (NaN = not seen), so association is exact.
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "plugslam/aligner_slice.h"
#include "plugslam/frame.h"
#include "plugslam/multi_tracker.h"
#include "plugslam/pipeline.h"
#include "plugslam/tracker_slice.h"

namespace plugslam::testing {

using Landmarks = std::vector<Eigen::Vector2d>;

/// A world of landmarks on a grid of `step` over [-extent, extent]^2, each moved by up to 0.3 m
/// in x and y (random from `seed`, so every run builds the same world).
Landmarks jitteredGrid(double step, double extent, unsigned seed);

/// Point-to-point factors between measured and mapped landmarks of the same id.
class LandmarkSliceBase : public AlignerSlice<Space2D> {
 public:
  Input<Landmarks> measurement{this, Container::measurement, "measurement", "landmarks",
                               "measured landmarks"};
  Input<Landmarks> scene{this, Container::scene, "scene", "landmarks", "mapped landmarks"};
  void linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const override;

 protected:
  /// The information of each landmark's factor.
  virtual double information() const = 0;
};

/// The landmark slice with its noise as a sigma.
class LandmarkSlice : public LandmarkSliceBase {
 public:
  Param<double> sigma{this, "sigma", 0.01, "m", "measurement noise"};

 protected:
  double information() const override { return 1.0 / (sigma() * sigma()); }
};

/// Adds newly seen landmarks to the scene (in the scene frame).
class LandmarkMapSlice : public TrackerSlice<Space2D> {
 public:
  Input<Landmarks> measurement{this, Container::measurement, "measurement", "landmarks",
                               "measured landmarks"};
  Output<Landmarks> scene{this, Container::scene, "scene", "landmarks", "mapped landmarks"};

 protected:
  void integrate(const MergeContext<Space2D>& context) override;
};

/// Registers both as "lmtest.LandmarkSlice" / "lmtest.LandmarkMapSlice" (once).
void registerLandmarkCue();

/// Landmarks of `world` within `range` of the robot at `pose`, in the robot frame.
Landmarks observe(const Landmarks& world, const Eigen::Isometry2d& pose, double range);

/// A 2D Multi-Tracker of this cue alone, built through the registry as a config builds it, that
/// closes its local map every `split_distance` metres.
std::shared_ptr<MultiTracker<Space2D>> landmarkTracker(double split_distance);

/// A pipeline that only tracks: it places each local map the tracker starts and composes the
/// frames' world poses, as every run does.
std::unique_ptr<Pipeline> trackingOnly(std::shared_ptr<Tracker> tracker);

/// An empty frame `seq` of a 10 Hz sequence.
Frame sequenceFrame(uint64_t seq);

}  // namespace plugslam::testing
