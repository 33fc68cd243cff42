#pragma once
// An edge of the pose graph of local maps: the tracker's relative pose between consecutive maps,
// or a validated loop closure.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

/// An edge of the pose graph between two local maps.
struct GraphEdge {
  int64_t from = 0;  ///< older map
  int64_t to = 0;    ///< newer map
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  ///< origin of `to` in `from`'s frame
  Eigen::MatrixXd information;  ///< tangent-space information (x, y, theta / x, y, z, rotation vector)
  bool loop = false;            ///< a loop closure (else: consecutive maps)
};

/// An edge's information in the error coordinates of the solver's between factors (identical in
/// 2D; in 3D the rotation part is the quaternion's vector part, half the rotation vector).
Eigen::MatrixXd betweenFactorInformation(const GraphEdge& edge, int dimension);

/// The graph component of each of maps 0..maps-1 that `edges` join (odometry and loops alike),
/// named by its lowest map id: maps of one component have a common frame, others none.
std::vector<int64_t> graphComponents(size_t maps, const std::vector<GraphEdge>& edges);

}  // namespace abi_v1
}  // namespace plugslam
