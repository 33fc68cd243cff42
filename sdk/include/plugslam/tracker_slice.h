#pragma once
// TrackerSlice: merges one cue of the measurement into its entry of the scene (the local map).
// It declares what it reads (Input<T>, typically a measurement entry) and the scene entry it
// writes (Output<T>, Container::scene); the SDK binds them before it calls integrate().
#include <cstdint>

#include "plugslam/configurable.h"
#include "plugslam/entry.h"
#include "plugslam/frame.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// What a tracker slice knows about the frame being merged, besides its entries.
template <class S>
struct MergeContext {
  typename S::Pose pose;  ///< the robot in the scene's frame
  uint64_t seq = 0;       ///< the frame's index in the run
  double stamp = 0;       ///< the frame's time [s]
};

/// One cue's part of the Multi-Tracker.
template <class S>
class TrackerSlice : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "TrackerSlice2D" : "TrackerSlice3D";
  using Pose = typename S::Pose;
  ~TrackerSlice() override;

  /// Integrates this frame's cue into the scene, the robot being at `t` in the scene's frame:
  /// binds the entries (reads to the frame's containers or the scene, scene outputs to `scene`)
  /// and calls integrate(), unless a read entry is absent this frame.
  void merge(const Frame& frame, PropertyContainer& scene, const Pose& t);

 protected:
  /// Merges the bound inputs into the bound scene outputs.
  virtual void integrate(const MergeContext<S>& context) = 0;
};

extern template class TrackerSlice<Space2D>;
extern template class TrackerSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
