#pragma once
// MotionModel: predicts the robot's motion between two frames (e.g. from wheel odometry).
#include <optional>

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

extern template class MotionModel<Space2D>;
extern template class MotionModel<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
