#pragma once
// The Multi-Tracker (seed, section IV-B): one local map (a scene container with one entry per
// cue), a Multi-Aligner, tracker slices that merge each cue, an optional motion model and a
// splitter. track() reads like the seed: predict (a mean and a covariance), align (search the
// window the covariance sets, refine with the prediction as a factor), merge, split.
#include <memory>
#include <optional>
#include <utility>

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
  // Without a motion model's reading the robot keeps its velocity; how wrong that can be is
  // what its acceleration can change over the time since the last frame.
  Param<double> max_acceleration = maxAccelerationParam(
      this,
      "largest plausible linear acceleration: sets the uncertainty of a constant-velocity "
      "prediction (no motion model reading)");
  Param<double> max_angular_acceleration = maxAngularAccelerationParam(
      this,
      "largest plausible angular acceleration: sets the heading uncertainty of a "
      "constant-velocity prediction");
  Param<std::vector<double>> fallback_sigma{
      this, "fallback_sigma",
      S::kDim == 2 ? std::vector<double>{0.1, 0.1, 0.05}
                   : std::vector<double>{0.1, 0.1, 0.1, 0.05, 0.05, 0.05},
      "m, rad",
      "std. dev. added to the prediction's for the edge of a frame whose alignment failed (per "
      "tangent coordinate)"};

  // Off by default: on laser scans a frame that fails against the current map can align wrongly
  // against the previous one (measured: Slam.FreiburgCampusStaysInOnePiece breaks with it on).
  Param<bool> align_previous_map{this, "align_previous_map", false, "",
                                 "when the alignment against the current local map fails, align "
                                 "against the one before it through the edge between them (a split "
                                 "left the views just behind the camera there)"};
  Param<bool> hand_over{this, "hand_over", true, "",
                        "on a split, slices that can (the landmark cue) start the new local map "
                        "with what the splitting frame sees of the old one, not from that frame "
                        "alone"};

  Param<double> localize_tie{
      this,
      "localize_tie",
      0.02,
      "",
      "localization (the sdk.Localizer this tracker hands over): saved maps whose alignment's "
      "inlier ratio is within this of the best are equally good, and the one nearest the "
      "motion prediction wins",
      Range{0, 1}};

  void configure() override;
  int dimension() const override { return S::kDim; }
  TrackEvents track(Frame& frame) override;
  /// The robot's pose in the current local map.
  const Pose& pose() const { return pose_; }
  /// Starts over: the current map is closed, no motion history; the next frame starts a new map
  /// (a new graph component, at the world origin). Also the action "reset".
  void reset();
  void continueSession(int64_t next_id) override;
  std::shared_ptr<Tracker> localizer(
      std::vector<std::shared_ptr<const LocalMap>> maps) const override;

 private:
  // The aligner's solution for this frame against `scene` (`to_scene`: the current map's origin
  // in the scene's frame), returned in the current map's frame.
  AlignResult<S> align(const Frame& frame, const PropertyContainer& scene, const Pose& to_scene,
                       const Pose& previous, const Pose& guess,
                       const MotionEstimate<S>& predicted);
  // The constant-velocity model's bounds (max_acceleration, max_angular_acceleration).
  ConstantVelocityBounds bounds() const;
  // Counts the frame as aligned or failed.
  void count(const Frame& frame, const AlignResult<S>& aligned);
  // What the splitter is asked after the frame was merged.
  SplitQuery splitQuery(const Frame& frame, const AlignResult<S>& aligned) const;
  // Information of the edge into a map started by a failed frame: the prediction's covariance
  // (kept as the frame's pose) widened by fallback_sigma.
  typename S::Matrix fallbackInformation(const typename S::Matrix& prediction) const;
  void merge(const Frame& frame);
  // Seeds the map just started at `origin` (in `previous`'s frame) by a split: slices that hand
  // over carry what the frame sees, the others merge the frame.
  void seedAfterSplit(const Frame& frame, const LocalMap& previous, const Pose& origin);
  void writeEstimate(Frame& frame, bool lost, bool unchecked = false) const;
  // Closes the current map (if any) and starts the next at the robot's pose, joined to it by
  // `information`.
  void startLocalMap(const Frame& frame, const typename S::Matrix& information,
                     TrackEvents& events);

  std::shared_ptr<LocalMap> map_;
  std::shared_ptr<LocalMap> previous_map_;         // the map before map_ (align_previous_map)
  Pose origin_in_previous_ = Pose::Identity();     // map_'s origin in previous_map_'s frame
  std::vector<std::shared_ptr<LocalMap>> closed_;  // by reset(), reported by the next track()
  Pose pose_ = Pose::Identity();                   // robot in the current local map
  MotionPrediction<S> prediction_;
  size_t frames_in_map_ = 0;
  int64_t next_id_ = 0;
};

extern template class MultiTracker<Space2D>;
extern template class MultiTracker<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
