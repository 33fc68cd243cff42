#pragma once
// Pose-graph files: g2o (VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, EDGE_SE3:QUAT, FIX) read and
// write; TORO / HOG-Man 2D (VERTEX2, EDGE2) and 3D (VERTEX3, EDGE3) read. Malformed input throws
// ParseError with the 1-based line.
#include <Eigen/Core>
#include <cstddef>
#include <iosfwd>
#include <string>

#include "plugslam/solver/factor_graph.h"

namespace plugslam {
inline namespace abi_v1 {

/// Reading options.
struct ReadGraphOptions {
  /// Replace each information matrix that is not positive definite with the nearest positive
  /// definite one (eigenvalues clamped); otherwise such matrices are kept and only counted.
  bool project_information = false;
};

/// What a graph file held.
struct GraphFileInfo {
  int dimension = 0;                 ///< 2 or 3
  std::string format;                ///< "g2o" or "toro"
  size_t vertices = 0;               ///< vertex records in the file
  size_t edges = 0;                  ///< edge records
  size_t fixed = 0;                  ///< variables fixed by FIX records
  bool has_vertices = false;         ///< false: estimates are not from the file; initialise them
  size_t non_pd_information = 0;     ///< edges whose information is not positive definite
  size_t projected_information = 0;  ///< of those, how many were projected
  size_t skipped_records = 0;        ///< records of other known-looking types (e.g. EQUIV)
  /// The order EDGE2 information was read in: "toro" (xx xy yy tt xt yt), "g2o" (xx xy xt yy yt
  /// tt: only when that order is positive definite for every EDGE2 and TORO's is not), or empty
  /// without EDGE2 records. Appended in ABI 2.3.
  std::string edge2_information_order;
};

/// Reads a g2o or TORO file into an empty graph (SE2/SE3 variables, between factors).
GraphFileInfo readGraphFile(const std::string& path, FactorGraph& graph,
                            const ReadGraphOptions& options = {});
/// Reads from a stream; name is used in error messages.
GraphFileInfo readGraph(std::istream& in, const std::string& name, FactorGraph& graph,
                        const ReadGraphOptions& options = {});

/// Writes SE2/SE3 variables, FIX lines and SE2/SE3 between factors in g2o format, atomically
/// (temporary file then rename). Returns the number of factors of other types left out.
size_t writeGraphFile(const std::string& path, const FactorGraph& graph);
/// Writes to a stream; see writeGraphFile.
size_t writeGraph(std::ostream& out, const FactorGraph& graph);

/// True when the symmetric matrix m is positive definite.
bool isPositiveDefinite(const Eigen::MatrixXd& m);
/// The positive definite matrix nearest to symmetric m: eigenvalues clamped to at least
/// min_ratio * the largest |eigenvalue| (and > 0).
Eigen::MatrixXd nearestPositiveDefinite(const Eigen::MatrixXd& m, double min_ratio = 1e-6);

}  // namespace abi_v1
}  // namespace plugslam
