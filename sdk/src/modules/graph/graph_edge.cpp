#include "plugslam/graph_edge.h"

namespace plugslam {
inline namespace abi_v1 {

Eigen::MatrixXd betweenFactorInformation(const GraphEdge& edge, int dimension) {
  if (dimension == 2) return edge.information;
  // The tracker's information is over the rotation vector; the factor's rotation error is half
  // of it, so the rotation block scales by 2 on each side.
  Eigen::Matrix<double, 6, 1> d;
  d << 1, 1, 1, 2, 2, 2;
  return d.asDiagonal() * edge.information * d.asDiagonal();
}

}  // namespace abi_v1
}  // namespace plugslam
