#pragma once
// Sessions: a folder holding what a run built, so a later run can extend it (multi-session
// mapping) or localize in it. Layout (every file written atomically, session.yaml last):
//   session.yaml    format version, dimension, counts, the file list
//   config.yaml     the YAML document the run was built from
//   maps.bin        binary archive: every local map (scene, origin, edge to its predecessor)
//                   and the graph's edges exactly as the back-end holds them
//   graph.g2o       the pose graph (when the back-end can write one), for other tools
//   trajectory.tum  the run's trajectory with every correction applied
#include <memory>
#include <string>
#include <vector>

#include "plugslam/graph_slam.h"
#include "plugslam/local_map.h"
#include "plugslam/pipeline.h"

namespace plugslam::runtime {

/// The session format this build writes and reads; other versions are refused.
constexpr int kSessionFormatVersion = 1;

/// What session.yaml says.
struct SessionManifest {
  std::string dir;
  int format_version = 0;
  int dimension = 0;
  size_t maps = 0, edges = 0;
  std::string config_text;  ///< content of config.yaml
  std::string config_path;  ///< dir/config.yaml
};

/// The maps and edges of a session.
struct SessionMaps {
  std::vector<std::shared_ptr<LocalMap>> maps;
  std::vector<GraphEdge> edges;
};

/// What saveSession wrote.
struct SessionSummary {
  size_t maps = 0, edges = 0, poses = 0;
  bool graph_file = false;
};

/// Writes the pipeline's current state as a session folder (created if missing). The pipeline
/// must not be processing a frame meanwhile.
SessionSummary saveSession(const std::string& dir, const std::string& config_yaml,
                           Pipeline& pipeline);
/// Writes `result` (its maps, edges and trajectory) as a session of `dimension`; `graph` (may be
/// null) writes graph.g2o.
SessionSummary saveSession(const std::string& dir, const std::string& config_yaml,
                           const RunResult& result, int dimension, GraphBackend* graph);
/// Reads session.yaml and config.yaml; a missing file or another format version throws
/// InputError saying what was found and what this build reads.
SessionManifest readSessionManifest(const std::string& dir);
/// Reads maps.bin (the config's plugins must be loaded: scenes hold their value types).
SessionMaps loadSessionMaps(const SessionManifest& manifest);
/// Deep copies of the maps (scenes included), so a run never alters what was loaded.
std::vector<std::shared_ptr<LocalMap>> copyMaps(const std::vector<std::shared_ptr<LocalMap>>& maps);

}  // namespace plugslam::runtime
