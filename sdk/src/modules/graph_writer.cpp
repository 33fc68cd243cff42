#include "plugslam/graph_writer.h"

namespace plugslam {
inline namespace abi_v1 {

void GraphWriter::end(const RunResult& result) {
  if (result.local_maps.empty()) return;
  writeGraphG2o(out_dir_ + "/" + file(), result.local_maps, result.edges);
}

}  // namespace abi_v1
}  // namespace plugslam
