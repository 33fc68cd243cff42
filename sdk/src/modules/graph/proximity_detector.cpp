#include "plugslam/proximity_detector.h"

namespace plugslam {
inline namespace abi_v1 {

std::vector<LoopCandidate> ProximityDetector::detect(const GraphView& view,
                                                     const LocalMap& query) {
  const DriftGate gate{radius(), drift(), max_radius(), min_travel()};
  std::vector<LoopCandidate> out;
  for (const auto& [distance, id] :
       spreadAlongPath(view, gate.near(view, query.id), max_candidates(), spacing())) {
    LoopCandidate c;
    c.id = id;
    c.score = distance;
    out.push_back(c);
  }
  return out;
}

}  // namespace abi_v1
}  // namespace plugslam
