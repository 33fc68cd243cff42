#include "plugslam/splitter.h"

namespace plugslam {
inline namespace abi_v1 {

Splitter::~Splitter() = default;

bool DistanceSplitter::split(const SplitQuery& q) const {
  return (distance() > 0 && q.distance >= distance()) || (angle() > 0 && q.angle >= angle()) ||
         (time() > 0 && q.elapsed >= time()) ||
         (min_inlier_ratio() > 0 && q.inlier_ratio < min_inlier_ratio());
}

}  // namespace abi_v1
}  // namespace plugslam
