#include "plugslam/pipeline.h"

#include "plugslam/errors.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

Pipeline::Pipeline() = default;
Pipeline::~Pipeline() = default;

void Pipeline::process(Frame& frame) {
  // Ground truth is recorded as it comes, so any pipeline can be scored against it.
  if (const auto* gt2 = frame.raw.find<Eigen::Isometry2d>("ground_truth"))
    ground_truth_.push_back({frame.stamp, Space2D::to3D(*gt2)});
  else if (const auto* gt3 = frame.raw.find<Eigen::Isometry3d>("ground_truth"))
    ground_truth_.push_back({frame.stamp, *gt3});
  for (auto& p : preprocessors) guarded(*p, [&] { return p->process(frame); });
  if (!tracker) return;
  guarded(*tracker, [&] { tracker->track(frame); });
  for (auto& closed : tracker->takeClosed()) local_maps_[closed->id] = closed;
  if (auto current = tracker->current())
    local_maps_[current->id] = std::const_pointer_cast<LocalMap>(current);
  if (frame.estimate.valid)
    tracked_.push_back({frame.stamp, frame.estimate.local_map, frame.estimate.in_map});
}

RunResult Pipeline::result() const {
  RunResult r;
  for (const auto& [id, map] : local_maps_) r.local_maps.push_back(map);
  double last = -std::numeric_limits<double>::infinity();
  for (const auto& f : tracked_) {
    // Frames with repeated or backward stamps are skipped: trajectories are strictly ordered.
    if (!(f.stamp > last)) continue;
    last = f.stamp;
    auto it = local_maps_.find(f.local_map);
    if (it == local_maps_.end()) continue;
    r.trajectory.push_back(f.stamp, it->second->origin * f.in_map);
  }
  last = -std::numeric_limits<double>::infinity();
  for (const auto& g : ground_truth_) {
    if (!(g.t > last)) continue;
    last = g.t;
    r.ground_truth.push_back(g.t, g.pose);
  }
  return r;
}

void Pipeline::throwModuleError(const Configurable& m, const std::string& what) {
  throw ModuleError(m.name(), m.typeName(), what);
}

}  // namespace abi_v1
}  // namespace plugslam
