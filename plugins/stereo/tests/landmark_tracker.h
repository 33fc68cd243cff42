#pragma once
// The landmark-cue tracker of configs/stereo_*.yaml and configs/sim3d_stereo.yaml, built in code
// for the tests: one reprojection slice, one landmark-map slice, a distance splitter.
#include <memory>

#include "plugslam/landmarks/landmark_slices.h"
#include "plugslam/multi_tracker.h"

namespace plugslam::testing {

/// Configures `tracker` with the default landmark slices and a split every `split_distance` m.
inline void buildLandmarkTracker(MultiTracker<Space3D>& tracker, double split_distance) {
  auto aligner = std::make_shared<MultiAligner<Space3D>>();
  auto slice = std::make_shared<ReprojectionSlice<Space3D>>();
  slice->configure();
  aligner->slices.assign(slice);
  aligner->configure();
  tracker.aligner.assign(aligner);
  auto merge = std::make_shared<LandmarkMapSlice<Space3D>>();
  merge->configure();
  tracker.slices.assign(merge);
  auto splitter = std::make_shared<DistanceSplitter>();
  splitter->distance.set(split_distance);
  tracker.splitter.assign(splitter);
  tracker.configure();
}

}  // namespace plugslam::testing
