#pragma once
// The pose graph as an output: local maps as vertices, tracker and loop edges ("sdk.GraphWriter").
#include <string>

#include "plugslam/sink.h"

namespace plugslam {
inline namespace abi_v1 {

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
