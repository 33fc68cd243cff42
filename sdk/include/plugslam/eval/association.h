#pragma once
// Pairing the poses of two trajectories by timestamp.
#include <cstddef>
#include <vector>

#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

/// How poses are paired by time.
struct AssociationOptions {
  /// Largest |t_ref - (t_est + time_offset)| accepted as the same instant (s).
  double max_time_diff = 0.01;
  /// Added to every estimate timestamp before matching (s).
  double time_offset = 0.0;
};

/// Index of a reference pose and of the estimate pose taken at the same time.
struct PosePair {
  std::size_t ref = 0;
  std::size_t est = 0;
};

/// Pairs each estimate pose with the nearest reference pose in time (one-to-one, in time order;
/// if two estimates pick the same reference pose the closer one wins). Throws InputError
/// "no overlap: reference spans [a, b], estimate spans [c, d] ..." when nothing associates.
std::vector<PosePair> associate(const Trajectory& reference, const Trajectory& estimate,
                                const AssociationOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
