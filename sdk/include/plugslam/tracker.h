#pragma once
// Tracker: the dimension-agnostic face of the front-end that the pipeline drives. A tracker
// knows poses in its local maps only: each map's place in the world is the pipeline's and the
// graph back-end's (see TrackEvents).
#include <memory>
#include <vector>

#include "plugslam/align_failure.h"
#include "plugslam/configurable.h"
#include "plugslam/frame.h"
#include "plugslam/local_map.h"

namespace plugslam {
inline namespace abi_v1 {

/// Counters a tracker keeps over a run.
struct TrackerStats {
  uint64_t frames = 0;    ///< frames tracked
  uint64_t aligned = 0;   ///< frames whose alignment was valid
  uint64_t failed = 0;    ///< frames where the aligner gave no valid or plausible solution
  uint64_t searched = 0;  ///< frames whose solve started from the correlative search
  /// Frames whose search found a distinct pose nearly as good (a corridor, a look-alike): the
  /// prediction chose, and their information along the rival's direction was cut.
  uint64_t ambiguous = 0;
  /// Frames whose pose came from a hypothesis made without the prediction (descriptor matching
  /// and RANSAC), which explained more of the frame than the solve from the prediction.
  uint64_t hypotheses = 0;
  /// Frames whose converged solve could not be checked (see AlignResult::unchecked).
  uint64_t unchecked = 0;
  /// Their indices (the first kMaxListed), for the run's report.
  std::vector<uint64_t> unchecked_frames;
  static constexpr std::size_t kMaxListed = 1000;  ///< frames listed at most
  double search_s = 0;          ///< [s] spent in the aligner's correlative search
  double refine_s = 0;          ///< [s] spent in the aligner's solve
  double merge_s = 0;           ///< [s] spent merging frames into local maps
  uint64_t local_maps = 0;      ///< local maps created
  double inlier_ratio_sum = 0;  ///< for the mean inlier ratio
  /// The failed frames by reason (index: AlignFailure); they sum to `failed`.
  uint64_t failures[kAlignFailures] = {};
  /// Counts one failed frame with its reason.
  void countFailure(AlignFailure reason) {
    ++failed;
    ++failures[static_cast<std::size_t>(reason)];
  }
};

/// What one track() did to the local maps, in the order the graph back-end takes it.
struct TrackEvents {
  /// The local map this frame started, if any: its `previous`, `relative` and `information`
  /// say how it follows its predecessor. The pipeline places it (origin = the predecessor's
  /// origin times `relative`); from then its origin belongs to the graph back-end.
  std::shared_ptr<LocalMap> started;
  /// Local maps closed since the last frame, oldest first: complete, nothing merges into them.
  std::vector<std::shared_ptr<LocalMap>> closed;
};

/// Tracks frames against a local map and splits local maps off.
class Tracker : public Configurable {
 public:
  static constexpr const char* kKind = "Tracker";
  ~Tracker() override;
  /// 2 or 3.
  virtual int dimension() const = 0;
  /// Predicts, aligns, merges and splits for one preprocessed frame; fills frame.estimate (all
  /// but `world`, which the pipeline composes from the map's origin) and says which local maps
  /// started and closed.
  virtual TrackEvents track(Frame& frame) = 0;
  /// Counters so far.
  const TrackerStats& stats() const { return stats_; }
  /// Continues a restored session: the next local map gets id `next_id` and starts a new
  /// component of the graph (no edge to the restored maps until a loop joins them). The default
  /// throws InputError: the tracker cannot extend a session.
  virtual void continueSession(int64_t next_id);
  /// A tracker that localizes in these frozen maps (world origins fixed) with this tracker's
  /// aligner and motion model, never merging into them nor creating maps: the pipeline tracks
  /// with it instead (`run --localize`). The default throws InputError: the tracker cannot
  /// localize.
  virtual std::shared_ptr<Tracker> localizer(
      std::vector<std::shared_ptr<const LocalMap>> maps) const;
  /// Continues from the robot's pose `world` in the maps' world frame, velocity unknown (a
  /// localizer that locked on by place recognition). The default throws InputError.
  virtual void relocate(const Eigen::Isometry3d& world);

 protected:
  TrackerStats stats_;
};

}  // namespace abi_v1
}  // namespace plugslam
