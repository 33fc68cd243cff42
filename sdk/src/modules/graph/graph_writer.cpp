#include "plugslam/graph_writer.h"

#include "plugslam/pose_space.h"
#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/graph_io.h"
#include "plugslam/solver/pose_factors.h"

namespace plugslam {
inline namespace abi_v1 {

void writeGraphG2o(const std::string& path, const std::vector<std::shared_ptr<const LocalMap>>& maps,
                   const std::vector<GraphEdge>& edges) {
  FactorGraph graph;
  const int dim = maps.empty() ? 2 : maps.front()->dimension;
  for (const auto& m : maps) {
    if (dim == 2)
      graph.addVariable<VariableSE2>(m->id, Space2D::from3D(m->origin));
    else
      graph.addVariable<VariableSE3>(m->id, m->origin);
  }
  if (!maps.empty()) graph.findVariable(maps.front()->id)->setFixed(true);
  for (const auto& e : edges) {
    Variable* a = graph.findVariable(e.from);
    Variable* b = graph.findVariable(e.to);
    if (!a || !b) continue;
    if (dim == 2)
      graph.emplaceFactor<BetweenFactorSE2>(static_cast<VariableSE2*>(a), static_cast<VariableSE2*>(b),
                                            Space2D::from3D(e.relative),
                                            Eigen::Matrix3d(betweenFactorInformation(e, 2)));
    else
      graph.emplaceFactor<BetweenFactorSE3>(
          static_cast<VariableSE3*>(a), static_cast<VariableSE3*>(b), e.relative,
          Eigen::Matrix<double, 6, 6>(betweenFactorInformation(e, 3)));
  }
  writeGraphFile(path, graph);
}

void GraphWriter::end(const RunResult& result) {
  if (result.local_maps.empty()) return;
  writeGraphG2o(out_dir_ + "/" + file(), result.local_maps, result.edges);
}

}  // namespace abi_v1
}  // namespace plugslam
