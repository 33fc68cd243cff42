#pragma once
// A minimal synthetic cue for testing the generic core modules without any sensor plugin:
// landmarks with known identities. The measurement and the scene hold a
// std::vector<Eigen::Vector2d> indexed by landmark id (NaN = not seen), so association is exact.
#include <Eigen/Core>
#include <vector>

#include "plugslam/aligner_slice.h"
#include "plugslam/tracker_slice.h"

namespace plugslam::testing {

using Landmarks = std::vector<Eigen::Vector2d>;

/// Point-to-point factors between measured and mapped landmarks of the same id.
class LandmarkSlice : public AlignerSlice<Space2D> {
 public:
  Param<std::string> entry{this, "entry", "landmarks", "", "measurement and scene entry"};
  Param<double> sigma{this, "sigma", 0.01, "m", "measurement noise"};
  bool bind(const Frame& frame, const PropertyContainer& scene,
            const AlignContext<Space2D>&) override;
  void linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const override;

 private:
  const Landmarks* measured_ = nullptr;
  const Landmarks* mapped_ = nullptr;
};

/// Adds newly seen landmarks to the scene (in the scene frame).
class LandmarkMapSlice : public TrackerSlice<Space2D> {
 public:
  Param<std::string> entry{this, "entry", "landmarks", "", "measurement and scene entry"};
  void merge(const Frame& frame, PropertyContainer& scene, const Eigen::Isometry2d& t) override;
};

/// Registers both as "lmtest.LandmarkSlice" / "lmtest.LandmarkMapSlice" (once).
void registerLandmarkCue();

/// Landmarks of `world` within `range` of the robot at `pose`, in the robot frame.
Landmarks observe(const Landmarks& world, const Eigen::Isometry2d& pose, double range);

}  // namespace plugslam::testing
