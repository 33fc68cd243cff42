#pragma once
// Merging saved sessions (`plugslam merge`): their graphs restored side by side, each its own
// component with no known relative pose, joined only by loops that place recognition found and
// the validators and loop filters accepted, then optimized as one and written as one session.
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace plugslam::runtime {

class PluginManager;

/// What `plugslam merge` is asked.
struct MergeOptions {
  std::vector<std::string> sessions;  ///< session folders; the first one's config is used
  std::vector<std::string> sets;      ///< PATH=VALUE overrides of that config
  std::string out_dir;                ///< the merged outputs and OUT/session
};

/// One input session in the merge.
struct MergedInput {
  std::string dir;
  size_t maps = 0;
  int64_t first_id = 0;  ///< its first map's id in the merged graph
  bool joined = false;   ///< joined to the first session by loops (else left out)
  size_t links = 0;      ///< loops between its maps and other sessions' maps
  size_t poses = 0;      ///< poses of its trajectory, re-expressed in the merged frame
  std::string trajectory_file;  ///< OUT/trajectory_K.tum (empty when not joined)
};

/// A loop between maps of two sessions, in the merged graph.
struct MergeLink {
  int64_t from = 0, to = 0;            ///< merged map ids
  double from_stamp = 0, to_stamp = 0;  ///< their first frames' stamps (the maps' origins)
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  ///< `to`'s origin in `from`'s
};

/// What mergeSessions did.
struct MergeReport {
  std::vector<MergedInput> inputs;
  std::vector<MergeLink> link_list;  ///< every loop across sessions
  size_t maps = 0, edges = 0, links = 0;  ///< of the merged graph; links: loops across sessions
  double seconds = 0;
};

/// Merges the sessions. Sessions that share no place with the first are left out and reported
/// (joined false); when none does, nothing is written and the report says so. Throws InputError
/// on sessions of another dimension or cue set, or a config whose graph cannot search loops.
/// `plugins` loads the config's plugins and must outlive the call (the maps hold their types).
MergeReport mergeSessions(const MergeOptions& options, PluginManager& plugins);

/// merge.json's content.
std::string mergeReportJson(const MergeReport& report);

}  // namespace plugslam::runtime
