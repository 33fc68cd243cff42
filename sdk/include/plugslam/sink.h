#pragma once
// Sink: consumes what the pipeline produces (writers, viewer streams).
#include <memory>
#include <string>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/frame.h"
#include "plugslam/graph_edge.h"
#include "plugslam/local_map.h"
#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

/// The final state of a run, handed to every sink at the end.
struct RunResult {
  /// One pose per tracked frame, in the world frame, with every correction applied.
  Trajectory trajectory;
  /// The local maps with their final (corrected) origins, in creation order.
  std::vector<std::shared_ptr<const LocalMap>> local_maps;
  /// The pose graph's edges between local maps (empty without a graph back-end).
  std::vector<GraphEdge> edges;
  /// The reference trajectory when the source provides one (the pipeline's `reference` entry:
  /// ground truth, or e.g. the log's own corrected poses).
  Trajectory reference;
};

/// Receives each processed frame and the final result.
class Sink : public Configurable {
 public:
  static constexpr const char* kKind = "Sink";
  ~Sink() override;
  /// Called once before the first frame with the run's output folder.
  virtual void begin(const std::string& out_dir) { (void)out_dir; }
  /// Called after each frame is processed.
  virtual void consume(const Frame& frame) { (void)frame; }
  /// Called once at the end of the run; writes the final outputs (atomically).
  virtual void end(const RunResult& result) { (void)result; }
};

}  // namespace abi_v1
}  // namespace plugslam
