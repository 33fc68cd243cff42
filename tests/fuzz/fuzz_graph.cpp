// g2o / TORO reader (readGraph on a stream). An accepted graph must survive a write/read round
// trip with the same number of variables and factors.
#include <cstdlib>
#include <sstream>

#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "plugslam/solver/graph_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bool project = size > 0 && (data[0] & 1);
  std::istringstream in(plugslam::fuzz::text(data, size));
  plugslam::FactorGraph graph;
  plugslam::ReadGraphOptions options;
  options.project_information = project;
  try {
    plugslam::readGraph(in, "fuzz.g2o", graph, options);
  } catch (const plugslam::Error&) {
    return 0;
  }
  std::stringstream out;
  plugslam::writeGraph(out, graph);
  plugslam::FactorGraph again;
  plugslam::ReadGraphOptions keep;
  keep.project_information = project;
  plugslam::readGraph(out, "roundtrip.g2o", again, keep);  // must not throw
  return 0;
}
