#pragma once
// MotionModel: predicts the robot's motion between two frames (e.g. from wheel odometry), and
// the prediction a tracker makes from it.
#include <optional>
#include <string>

#include "plugslam/configurable.h"
#include "plugslam/entry.h"
#include "plugslam/frame.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// Predicts the relative motion since the previous frame it saw.
template <class S>
class MotionModel : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "MotionModel2D" : "MotionModel3D";
  using Pose = typename S::Pose;
  ~MotionModel() override;
  /// The motion since the previous call (in the previous robot frame), or nothing when this
  /// frame carries no usable reading.
  virtual std::optional<Pose> predict(const Frame& frame) = 0;
  /// Forgets the previous reading.
  virtual void reset() {}
};

/// A second base a motion model may add when part of its prediction is not measured but
/// extrapolated (a reading older than the frame, carried to the frame's time with the recent
/// velocity): how the robot moved in that part is known only to lie between standing still and
/// the extrapolation, so the tracker's correction gate and a motion prior widen by it.
template <class S>
class ExtrapolatingMotionModel {
 public:
  virtual ~ExtrapolatingMotionModel();
  /// How much of the last predict()'s motion was extrapolated rather than measured: a motion
  /// whose distance and angle bound that part (the guess the motion ends with, plus the one it
  /// starts from, whose error comes back in it); empty when all of it was measured.
  virtual std::optional<typename S::Pose> extrapolated() const = 0;
};

/// A second base a motion model may add to learn from the tracker: after each frame it aligned,
/// the tracker reports the motion it solved for the frame the model last predicted, so the model
/// can calibrate itself against the other cues (wheel odometry: wheel radii and the wheel base
/// differ from their nominal values).
template <class S>
class CalibratingMotionModel {
 public:
  virtual ~CalibratingMotionModel();
  /// The motion the tracker solved for the frame last predicted (in the previous robot frame);
  /// called only when the model predicted that frame and the frame was aligned, not lost.
  virtual void solved(const typename S::Pose& motion) = 0;
};

/// The pose a tracker predicts before aligning: the motion model's delta when it has one for the
/// frame, else the last motion again (constant velocity) or none.
template <class S>
struct MotionPrediction {
  using Pose = typename S::Pose;
  Pose last_motion = Pose::Identity();  ///< the motion of the last frame (constant velocity)
  /// The motion model's measured motion for the last frame (empty: the prediction did not come
  /// from it); the aligner's slices get it in their AlignContext.
  std::optional<Pose> model_motion;
  /// The raw entry `model_motion` was measured from when the model reads exactly one (a slice
  /// reading the same entry then takes that delta rather than computing it again); else empty.
  std::string model_entry;
  /// How much of `model_motion` the model extrapolated rather than measured
  /// (ExtrapolatingMotionModel::extrapolated()); empty when all of it was measured.
  std::optional<Pose> model_extrapolated;

  /// The pose predicted for `frame` from the robot's pose `from`.
  Pose predict(MotionModel<S>* model, bool constant_velocity, const Frame& frame,
               const Pose& from) {
    model_motion.reset();
    model_entry.clear();
    model_extrapolated.reset();
    if (model) {
      model_motion = model->predict(frame);
      if (model_motion) model_entry = soleRawInput(*model);
      if (const auto* e = dynamic_cast<const ExtrapolatingMotionModel<S>*>(model);
          e && model_motion)
        model_extrapolated = e->extrapolated();
    }
    const Pose delta =
        model_motion ? *model_motion : constant_velocity ? last_motion : Pose::Identity();
    return S::normalized(from * delta);
  }
  /// Forgets the motion history.
  void reset() {
    last_motion = Pose::Identity();
    model_motion.reset();
    model_entry.clear();
    model_extrapolated.reset();
  }

 private:
  // The name of the one raw entry `model` reads; empty when it reads none or several.
  static std::string soleRawInput(const MotionModel<S>& model) {
    std::string name;
    int inputs = 0;
    for (const EntryBase* e : model.entries())
      if (!e->writes() && e->container() == Container::raw) {
        ++inputs;
        name = e->name();
      }
    return inputs == 1 ? name : std::string();
  }
};

extern template class MotionModel<Space2D>;
extern template class MotionModel<Space3D>;
extern template class ExtrapolatingMotionModel<Space2D>;
extern template class ExtrapolatingMotionModel<Space3D>;
extern template class CalibratingMotionModel<Space2D>;
extern template class CalibratingMotionModel<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
