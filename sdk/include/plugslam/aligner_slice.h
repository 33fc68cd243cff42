#pragma once
// AlignerSlice: the part of the Multi-Aligner that handles one cue. It declares the entries it
// reads as typed members (Input<T>, see entry.h), typically a measurement entry and the scene
// entry it aligns against; the SDK binds them for each frame, the slice associates them at the
// current estimate and adds its factors on the one relative-pose variable through
// NormalEquations::add.
//   class MySlice : public AlignerSlice<Space2D> {
//     Input<PointCloud2D> measurement{this, Container::measurement, "measurement", "front", "..."};
//     Input<PointCloud2D> scene{this, Container::scene, "scene", "front", "..."};
//     void linearize(const Pose& t, NormalEquations<Space2D>& eq) const override {
//       for (auto [i, j] : pairs_) eq.add(PointToPoint2D{measurement->points[i], ...}, t, info);
//     }
//   };
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "plugslam/configurable.h"
#include "plugslam/entry.h"
#include "plugslam/frame.h"
#include "plugslam/normal_equations.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// What a slice knows about the frame being aligned, besides its entries.
template <class S>
struct AlignContext {
  using Pose = typename S::Pose;  ///< the pose type
  /// Previous pose and guess at the scene's origin, no measured motion.
  AlignContext() = default;
  /// The previous pose, the initial estimate, the motion model's measured motion and the raw
  /// entry it was measured from.
  AlignContext(const Pose& previous_pose, const Pose& initial_guess,
               std::optional<Pose> measured_motion = std::nullopt,
               std::string measured_entry = std::string())
      : previous(previous_pose),
        guess(initial_guess),
        motion(std::move(measured_motion)),
        motion_entry(std::move(measured_entry)) {}

  Pose previous = Pose::Identity();  ///< the previous frame's pose in the scene frame
  Pose guess = Pose::Identity();     ///< the initial estimate (the motion prediction)
  /// The covariance of `guess` (tangent space at it, right perturbation); empty when nothing
  /// predicted it (a loop's validation): the aligner then neither searches nor adds a prior.
  std::optional<typename S::Matrix> covariance;
  /// How many standard deviations of `covariance` a search covers (the aligner's search_sigmas):
  /// a cue that searches by its own means (projection windows) reaches as far.
  double search_sigmas = 3.0;
  /// The motion since the previous frame as the tracker's motion model measured it (in the
  /// previous robot frame); empty without a motion model or a reading this frame.
  std::optional<typename S::Pose> motion;
  uint64_t seq = 0;  ///< the frame's index in the run (set by bind from the frame)
  double stamp = 0;  ///< the frame's time [s] (set by bind from the frame)
  /// The raw entry `motion` was measured from, when the motion model reads exactly one (a slice
  /// that reads the same entry can take `motion` instead of computing it again); else empty.
  std::string motion_entry;
  /// The covariance of the prediction's typical errors where the run measured them
  /// (MotionPrediction::typical): the search favours poses within it; `covariance` bounds them.
  std::optional<typename S::Matrix> typical;
  /// After a gap in the stamps, the pose had the robot kept its velocity through it
  /// (MotionPrediction::through_gap, in the scene frame), with `covariance` about it: a guess the
  /// aligner also tries when the solve from `guess` cannot be vouched for. Empty otherwise.
  std::optional<Pose> through_gap;
};

/// One cue's contribution to the Multi-Aligner.
template <class S>
class AlignerSlice : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "AlignerSlice2D" : "AlignerSlice3D";
  using Pose = typename S::Pose;
  ~AlignerSlice() override;

  /// Binds the slice's entries to this frame (raw and measurement entries to the frame's
  /// containers, scene entries to `scene`, the local map in its own frame), then calls prepare().
  /// Returns false when an entry is absent or prepare() declines (the slice then adds nothing).
  bool bind(const Frame& frame, const PropertyContainer& scene, const AlignContext<S>& context);
  /// A solve starts from a new pose (the prediction, the search's or a hypothesis): association
  /// rounds start over (a slice that narrows its windows round by round widens them again).
  virtual void beginSolve() {}
  /// Data association at estimate T (scene <- robot); called once per outer iteration.
  virtual void associate(const Pose& t) { (void)t; }
  /// Adds the slice's linearised factors at T (NormalEquations::add); sets eq.candidates to the
  /// number of measurement elements it tried to associate when it knows it.
  virtual void linearize(const Pose& t, NormalEquations<S>& eq) const = 0;

 protected:
  /// Takes this frame's inputs once every entry is bound (none absent). Returns false when the
  /// cue is unusable this frame (for example an empty cloud). The default accepts.
  virtual bool prepare(const AlignContext<S>& context) {
    (void)context;
    return true;
  }
};

/// Optional second base of an aligner slice that can place the robot without the prediction
/// (wide-baseline relocalisation, e.g. descriptor matching + RANSAC). The Multi-Aligner asks it,
/// after bind(), for a hypothesis when its association cannot cover the prediction's
/// uncertainty, when the solve from the prediction is invalid, and when that solve cannot vouch
/// for the motion it found; it solves from the pose proposed and keeps what explains more.
template <class S>
class RecoverableSlice {
 public:
  virtual ~RecoverableSlice();
  /// A guess of the robot in the scene frame from this frame's bound entries alone; empty when
  /// the slice finds none.
  virtual std::optional<typename S::Pose> recoverPose() = 0;
  /// Whether this frame's association, started at the prediction, reaches as far as the
  /// prediction's covariance says it may be off (false: only recoverPose() can place the frame).
  virtual bool priorCovered() const { return true; }
};

extern template class AlignerSlice<Space2D>;
extern template class AlignerSlice<Space3D>;
extern template class RecoverableSlice<Space2D>;
extern template class RecoverableSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
