#pragma once
// TrackerSlice: merges one cue of the measurement into its entry of the scene (the local map).
#include "plugslam/configurable.h"
#include "plugslam/frame.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// One cue's part of the Multi-Tracker.
template <class S>
class TrackerSlice : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "TrackerSlice2D" : "TrackerSlice3D";
  using Pose = typename S::Pose;
  ~TrackerSlice() override;

  /// Integrates this frame's cue into the scene, the robot being at `t` in the scene's frame.
  virtual void merge(const Frame& frame, PropertyContainer& scene, const Pose& t) = 0;
};

extern template class TrackerSlice<Space2D>;
extern template class TrackerSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
