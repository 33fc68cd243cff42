#pragma once
// The Multi-Tracker (seed, section IV-B): one local map (a scene container with one entry per
// cue), a Multi-Aligner, tracker slices that merge each cue, an optional motion model and a
// splitter. compute() reads like the seed: predict, align, merge, split.
#include <memory>
#include <optional>
#include <string>

#include "plugslam/motion_model.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/splitter.h"
#include "plugslam/tracker.h"
#include "plugslam/tracker_slice.h"

namespace plugslam {
inline namespace abi_v1 {

/// Tracks frames against a local map made of any number of cues ("sdk.MultiTracker2D/3D").
template <class S>
class MultiTracker : public Tracker {
 public:
  using Pose = typename S::Pose;
  MultiTracker();
  ~MultiTracker() override;

  Slot<MultiAligner<S>> aligner{this, "aligner", std::string("sdk.MultiAligner") + S::kSuffix,
                                "solves for the robot pose against the local map"};
  SlotList<TrackerSlice<S>> slices{this, "slices", "merge each cue into the local map"};
  Slot<Splitter> splitter{this, "splitter", "sdk.DistanceSplitter",
                          "decides when a local map closes"};
  Slot<MotionModel<S>> motion{this, "motion", "",
                              "predicts motion between frames (default: constant velocity)"};
  Param<bool> constant_velocity{this, "constant_velocity", true, "",
                                "without a motion model, predict the last motion again"};
  Param<std::vector<double>> fallback_sigma{
      this, "fallback_sigma", S::kDim == 2 ? std::vector<double>{0.1, 0.1, 0.05}
                                           : std::vector<double>{0.1, 0.1, 0.1, 0.05, 0.05, 0.05},
      "m, rad", "std. dev. of an edge whose alignment failed (per tangent coordinate)"};

  // On sparse scans a few wrong pairs can outweigh the odometry prior and slide the pose far
  // from a prediction that was right; a correction larger than the motion model's error can be
  // is then a failed alignment, not a measurement.
  Param<std::vector<double>> max_correction{
      this, "max_correction", {}, "m, rad",
      "translation and rotation: an alignment farther than this from the motion model's "
      "prediction counts as failed and the prediction is kept (empty: no limit; not applied "
      "when the motion model has no prediction)"};

  Param<double> localize_tie{
      this, "localize_tie", 0.02, "",
      "localization: saved maps whose alignment's inlier ratio is within this of the best are "
      "equally good, and the one nearest the motion prediction wins",
      Range{0, 1}};

  void configure() override;
  int dimension() const override { return S::kDim; }
  void track(Frame& frame) override;
  std::vector<std::shared_ptr<LocalMap>> takeClosed() override;
  std::shared_ptr<const LocalMap> current() const override {
    return frozen_.empty() ? std::shared_ptr<const LocalMap>(map_) : located_;
  }
  void setCurrentOrigin(const Eigen::Isometry3d& origin) override;
  /// The robot's pose in the current local map.
  const Pose& pose() const { return pose_; }
  /// Starts over: the current map is closed, no motion history; the next frame starts a new map
  /// (a new graph component, at the world origin). Also the action "reset".
  void reset();
  void continueSession(int64_t next_id) override;
  void localizeIn(std::vector<std::shared_ptr<const LocalMap>> maps) override;

 private:
  Pose predict(const Frame& frame);
  // The aligner's context: the poses, and the motion model's measured motion with its entry.
  AlignContext<S> alignContext(const Pose& previous, const Pose& guess) const;
  void merge(const Frame& frame);
  void writeEstimate(Frame& frame, bool lost) const;
  void startLocalMap(const Frame& frame, const typename S::Matrix& information);
  void trackFrozen(Frame& frame);

  std::shared_ptr<LocalMap> map_;
  std::vector<std::shared_ptr<LocalMap>> closed_;
  Pose pose_ = Pose::Identity();         // robot in the current local map
  Pose last_motion_ = Pose::Identity();  // for the constant-velocity prediction
  size_t frames_in_map_ = 0;
  // The motion model's measured motion this frame (empty: the prediction did not come from it);
  // the aligner's slices get it in their AlignContext.
  std::optional<Pose> model_motion_;
  std::string model_motion_entry_;  // the raw entry it was measured from (see AlignContext)
  int64_t next_id_ = 0;
  // Localization mode: the frozen maps and the one the robot is in.
  std::vector<std::shared_ptr<const LocalMap>> frozen_;
  std::shared_ptr<const LocalMap> located_;
};

extern template class MultiTracker<Space2D>;
extern template class MultiTracker<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
