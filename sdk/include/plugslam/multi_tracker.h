#pragma once
// The Multi-Tracker (seed, section IV-B): one local map (a scene container with one entry per
// cue), a Multi-Aligner, tracker slices that merge each cue, an optional motion model and a
// splitter. track() reads like the seed: predict, align, merge, split.
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
  // Odometry's error grows with the motion it integrates: wheel scale and slip per metre driven,
  // skid per radian turned. Over a long step (a slow scan rate, a dropped scan) a right alignment
  // lands farther from the prediction than a fixed gate allows, so the gate grows with the
  // motion the model predicts since the last frame (the frame the local map already holds).
  Param<std::vector<double>> max_correction_per_motion{
      this, "max_correction_per_motion", {}, "m/m, m/rad, rad/m, rad/rad",
      "growth of the max_correction gate with the predicted motion since the last frame: "
      "translation per metre and per radian of it, rotation per metre and per radian; the gate "
      "is the larger of max_correction and this bound (empty: max_correction alone)"};

  // The aligner's seeder (a wide search around the prediction) proposes where a poor
  // prediction's frame really is. Within the gate its pose replaces the solve from the
  // prediction when it explains more of the scan. Beyond the gate it claims the odometry was
  // wrong (slip, a kidnap), which sparse scans also fake by looking alike elsewhere: that takes
  // far more support than the prediction's own solve.
  Param<double> seed_beyond_gate{
      this, "seed_beyond_gate", 0.0, "",
      "a seeder's pose beyond the correction gate counts when its solve has at least this many "
      "times the inliers of the solve from the prediction (0: never; no gate: always)",
      Range{0, 1e6}};

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
      this, "localize_tie", 0.02, "",
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
  // in the scene's frame), returned in the current map's frame; marked invalid when it moved the
  // motion model's prediction farther than max_correction.
  AlignResult<S> align(const Frame& frame, const PropertyContainer& scene, const Pose& to_scene,
                       const Pose& previous, const Pose& guess);
  // A frame whose motion was not measured, or only in part (extrapolated): the seeder's search
  // checks the solve from the prediction (in the scene's frame, like `aligned`), and its solve
  // replaces it when it explains more of the scan (within the correction gate, if one applies).
  AlignResult<S> checkUnmeasured(const Frame& frame, const PropertyContainer& scene,
                                 const AlignContext<S>& context,
                                 const std::optional<std::pair<double, double>>& gate,
                                 AlignResult<S> aligned);
  // Whether `pose` corrects `guess` (both in one frame) by more than `gate` (m, rad).
  static bool beyondGate(const std::pair<double, double>& gate, const Pose& guess,
                         const Pose& pose);
  // The gate (translation m, rotation rad) on this frame's correction from the prediction:
  // max_correction, grown with the predicted motion (max_correction_per_motion); empty when no
  // gate applies (no limit set, or the motion model predicted nothing).
  std::optional<std::pair<double, double>> correctionGate() const;
  // Counts the frame as aligned or failed.
  void count(const Frame& frame, const AlignResult<S>& aligned);
  // What the splitter is asked after the frame was merged.
  SplitQuery splitQuery(const Frame& frame, const AlignResult<S>& aligned) const;
  // Information of the edge into a map started by a failed frame (fallback_sigma).
  typename S::Matrix fallbackInformation() const;
  void merge(const Frame& frame);
  // Seeds the map just started at `origin` (in `previous`'s frame) by a split: slices that hand
  // over carry what the frame sees, the others merge the frame.
  void seedAfterSplit(const Frame& frame, const LocalMap& previous, const Pose& origin);
  void writeEstimate(Frame& frame, bool lost) const;
  // Closes the current map (if any) and starts the next at the robot's pose, joined to it by
  // `information`.
  void startLocalMap(const Frame& frame, const typename S::Matrix& information,
                     TrackEvents& events);

  std::shared_ptr<LocalMap> map_;
  std::shared_ptr<LocalMap> previous_map_;      // the map before map_ (align_previous_map)
  Pose origin_in_previous_ = Pose::Identity();  // map_'s origin in previous_map_'s frame
  std::vector<std::shared_ptr<LocalMap>> closed_;  // by reset(), reported by the next track()
  Pose pose_ = Pose::Identity();  // robot in the current local map
  MotionPrediction<S> prediction_;
  std::optional<Pose> motion_residual_;  // AlignContext::motion_residual for the next frame
  size_t frames_in_map_ = 0;
  int64_t next_id_ = 0;
};

extern template class MultiTracker<Space2D>;
extern template class MultiTracker<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
