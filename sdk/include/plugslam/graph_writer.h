#pragma once
// The pose graph as an output: local maps as vertices, tracker and loop edges, in g2o format. The
// one export of the graph: the run's graph.g2o ("sdk.GraphWriter"), GraphSlam's `save_graph`
// action, a session's graph.g2o.
#include <memory>
#include <string>
#include <vector>

#include "plugslam/graph_edge.h"
#include "plugslam/local_map.h"
#include "plugslam/sink.h"

namespace plugslam {
inline namespace abi_v1 {

/// Writes local maps (as vertices, at their origins; the first fixed) and edges as a g2o file,
/// atomically.
void writeGraphG2o(const std::string& path, const std::vector<std::shared_ptr<const LocalMap>>& maps,
                   const std::vector<GraphEdge>& edges);

/// Writes the final pose graph in g2o format into the run's output folder.
class GraphWriter : public Sink {
 public:
  Param<std::string> file{this, "file", "graph.g2o", "", "file name in the output folder"};
  void begin(const std::string& out_dir) override { out_dir_ = out_dir; }
  void end(const RunResult& result) override;

 private:
  std::string out_dir_;
};

}  // namespace abi_v1
}  // namespace plugslam
