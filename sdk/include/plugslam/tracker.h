#pragma once
// Tracker: the dimension-agnostic face of the Multi-Tracker that the pipeline drives.
#include <memory>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/frame.h"
#include "plugslam/local_map.h"

namespace plugslam {
inline namespace abi_v1 {

/// Counters a tracker keeps over a run.
struct TrackerStats {
  uint64_t frames = 0;          ///< frames tracked
  uint64_t aligned = 0;         ///< frames whose alignment was valid
  uint64_t failed = 0;          ///< frames where the aligner gave no valid or plausible solution
  uint64_t local_maps = 0;      ///< local maps created
  double inlier_ratio_sum = 0;  ///< for the mean inlier ratio
};

/// Tracks frames against a local map and splits local maps off.
class Tracker : public Configurable {
 public:
  static constexpr const char* kKind = "Tracker";
  ~Tracker() override;
  /// 2 or 3.
  virtual int dimension() const = 0;
  /// Predicts, aligns, merges and splits for one preprocessed frame; fills frame.estimate.
  virtual void track(Frame& frame) = 0;
  /// Local maps closed since the last call, oldest first (ownership moves to the caller).
  virtual std::vector<std::shared_ptr<LocalMap>> takeClosed() = 0;
  /// The local map being built (nullptr before the first frame).
  virtual std::shared_ptr<const LocalMap> current() const = 0;
  /// Moves the current map's world origin (after the back-end corrected the graph).
  virtual void setCurrentOrigin(const Eigen::Isometry3d& origin) = 0;
  /// Counters so far.
  const TrackerStats& stats() const { return stats_; }
  /// Continues a restored session: the next local map gets id `next_id` and starts a new
  /// component of the graph (no edge to the restored maps until a loop joins them). The default
  /// throws InputError: the tracker cannot extend a session.
  virtual void continueSession(int64_t next_id);
  /// Localization only: tracks against these frozen maps (world origins fixed), never merging
  /// into them nor creating maps. The default throws InputError: the tracker cannot localize.
  virtual void localizeIn(std::vector<std::shared_ptr<const LocalMap>> maps);

 protected:
  TrackerStats stats_;
};

}  // namespace abi_v1
}  // namespace plugslam
