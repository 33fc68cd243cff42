#include "plugslam/pipeline.h"

#include "plugslam/errors.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

Pipeline::Pipeline() = default;
Pipeline::~Pipeline() = default;

void Pipeline::process(Frame& frame) {
  // Ground truth is recorded as it comes, so any pipeline can be scored against it.
  // find<T> throws on another type, so ask which one the source wrote (2D or 3D) first.
  if (frame.raw.holds<Eigen::Isometry2d>("ground_truth"))
    ground_truth_.push_back(
        {frame.stamp, Space2D::to3D(frame.raw.get<Eigen::Isometry2d>("ground_truth"))});
  else if (frame.raw.holds<Eigen::Isometry3d>("ground_truth"))
    ground_truth_.push_back({frame.stamp, frame.raw.get<Eigen::Isometry3d>("ground_truth")});
  for (auto& p : preprocessors) guarded(*p, [&] { return p->process(frame); });
  if (!tracker) return;
  guarded(*tracker, [&] { tracker->track(frame); });
  auto closed = tracker->takeClosed();
  if (auto current = tracker->current()) {
    auto map = std::const_pointer_cast<LocalMap>(current);
    if (local_maps_.emplace(map->id, map).second && graph)
      guarded(*graph, [&] { graph->mapStarted(map); });
  }
  if (graph) {
    for (auto& map : closed) guarded(*graph, [&] { graph->mapClosed(map); });
    guarded(*graph, [&] { return graph->poll(); });
  }
  if (frame.estimate.valid)
    tracked_.push_back({frame.stamp, frame.estimate.local_map, frame.estimate.in_map});
}

void Pipeline::configure() {
  if (graph && !tracker) throw ParamError("graph", "a graph back-end needs a tracker");
  if (graph && graph->dimension() != tracker->dimension())
    throw ParamError("graph", "a " + std::to_string(graph->dimension()) +
                                  "D back-end cannot take the local maps of a " +
                                  std::to_string(tracker->dimension()) + "D tracker");
}

void Pipeline::finish() {
  if (graph) guarded(*graph, [&] { graph->finish(); });
}

RunResult Pipeline::result() const {
  RunResult r;
  if (graph) r.edges = graph->edges();
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
