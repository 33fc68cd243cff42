#pragma once
// TrackerSlice: merges one cue of the measurement into its entry of the scene (the local map).
// It declares what it reads (Input<T>, typically a measurement entry) and the scene entry it
// writes (Output<T>, Container::scene); the SDK binds them before it calls integrate().
#include <cstdint>
#include <optional>

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

/// Optional second base of a tracker slice that carries part of its scene entry into the next
/// local map when the tracker splits, so the new map continues with what the splitting frame
/// sees instead of restarting from that frame's measurement alone.
template <class S>
class HandoverSlice {
 public:
  virtual ~HandoverSlice();
  /// Fills this slice's entry of `next` (the new local map's scene, empty so far) from its entry
  /// of `previous` with what frame `seq` observed, in the new map's frame; `origin` is the new
  /// map's origin in the previous map's frame. The frame itself was merged into `previous`.
  virtual void handOver(const PropertyContainer& previous, PropertyContainer& next,
                        const typename S::Pose& origin, uint64_t seq) = 0;
};

/// Optional second base of a tracker slice whose merge refines the pose of the frame it merged
/// (a local bundle adjustment): the tracker takes the refined pose as the frame's estimate.
template <class S>
class RefiningSlice {
 public:
  virtual ~RefiningSlice();
  /// The frame just merged, refined (in the local map's frame); empty when the merge did not
  /// refine it.
  virtual std::optional<typename S::Pose> refinedPose() const = 0;
};

extern template class TrackerSlice<Space2D>;
extern template class TrackerSlice<Space3D>;
extern template class HandoverSlice<Space2D>;
extern template class HandoverSlice<Space3D>;
extern template class RefiningSlice<Space2D>;
extern template class RefiningSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
