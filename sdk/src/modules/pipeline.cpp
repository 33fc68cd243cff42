#include "plugslam/pipeline.h"

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"
#include "plugslam/pose_space.h"
#include "pose_log.h"

namespace plugslam {
inline namespace abi_v1 {

Pipeline::Pipeline()
    : tracked_(std::make_unique<detail::PoseLog>()),
      reference_(std::make_unique<detail::PoseLog>()) {}
Pipeline::~Pipeline() = default;

void Pipeline::process(Frame& frame) {
  // Ground truth is recorded as it comes, so any pipeline can be scored against it.
  if (frame.raw.holds<Eigen::Isometry2d>(reference()))
    reference_->push_back(
        {frame.stamp, 0, Space2D::to3D(frame.raw.get<Eigen::Isometry2d>(reference()))});
  else if (frame.raw.holds<Eigen::Isometry3d>(reference()))
    reference_->push_back({frame.stamp, 0, frame.raw.get<Eigen::Isometry3d>(reference())});
  for (auto& p : preprocessors) guarded(*p, [&] { return p->process(frame); });
  if (!tracker) return;
  const TrackEvents events = guarded(*tracker, [&] { return tracker->track(frame); });
  if (const auto& map = events.started) {
    // Placed where the tracker measured it from its predecessor (as the graph has that one now);
    // from here on the graph back-end owns its origin.
    if (map->previous >= 0) map->origin = localMap(map->previous).origin * map->relative;
    if (!local_maps_.emplace(map->id, map).second)
      throw ModuleError(tracker->name(), tracker->typeName(),
                        "started local map " + std::to_string(map->id) + " twice");
    if (graph) guarded(*graph, [&] { graph->mapStarted(map); });
  }
  if (frame.estimate.valid)
    frame.estimate.world = localMap(frame.estimate.local_map).origin * frame.estimate.in_map;
  if (graph) {
    for (const auto& map : events.closed) guarded(*graph, [&] { graph->mapClosed(map); });
    guarded(*graph, [&] { return graph->poll(); });
  }
  ++frames_;
  if (!searching_in_.empty() && frame.estimate.valid) lockOn(frame);
  if (frame.estimate.valid)
    tracked_->push_back({frame.stamp, frame.estimate.local_map, frame.estimate.in_map});
}

void Pipeline::lockOn(Frame& frame) {
  // Until a loop joins the run's maps to the saved ones, its poses are in a frame of its own.
  // The place the robot sees is searched at once, and again whenever its view changed, rather
  // than once its map closes: a robot switched on anywhere should know where it is in a few
  // frames.
  const Eigen::Isometry3d pose = frame.estimate.world;
  const Eigen::Isometry3d moved = last_search_ ? last_search_->inverse() * pose : pose;
  if (!last_search_ || moved.translation().norm() >= lost_search_spacing()[0] ||
      Eigen::AngleAxisd(moved.rotation()).angle() >= lost_search_spacing()[1]) {
    last_search_ = pose;
    guarded(*graph, [&] { return graph->relocalize(frame.estimate.local_map); });
  }
  // Only a new loop can join them: the graph's components are looked at when one came.
  const GraphStats stats = graph->stats();
  const uint64_t loops = stats.loops_accepted + stats.loops_rejected;
  bool joined = false;
  if (loops != loops_seen_) {
    loops_seen_ = loops;
    const std::vector<int64_t> components = graphComponents(local_maps_.size(), graph->edges());
    const auto here = static_cast<size_t>(frame.estimate.local_map);
    joined = here < components.size() && components[here] == components[0];
  }
  if (!joined) {
    frame.estimate.lost = true;
    return;
  }
  // Joined: once optimized with that loop (a threaded back-end may not have yet), the frame's
  // pose is in the saved maps' frame; localize from there.
  graph->optimizeNow();
  const Eigen::Isometry3d world = localMap(frame.estimate.local_map).origin * frame.estimate.in_map;
  std::shared_ptr<Tracker> localizer = tracker->localizer(searching_in_);
  localizer->relocate(world);
  tracker.assign(localizer);
  searching_in_.clear();
  locked_on_after_ = frames_ - 1;
  frame.estimate.world = world;
}

std::shared_ptr<const LocalMap> Pipeline::findLocalMap(int64_t id) const {
  const auto it = local_maps_.find(id);
  return it == local_maps_.end() ? nullptr : it->second;
}

const LocalMap& Pipeline::localMap(int64_t id) const {
  const auto it = local_maps_.find(id);
  if (it == local_maps_.end())
    throw ModuleError(tracker->name(), tracker->typeName(),
                      "refers to local map " + std::to_string(id) + ", which it never started");
  return *it->second;
}

void Pipeline::configure() {
  if (lost_search_spacing().size() != 2 || !(lost_search_spacing()[0] >= 0) ||
      !(lost_search_spacing()[1] >= 0))
    throw ParamError("lost_search_spacing", "expected 2 values >= 0 (translation m, rotation rad)");
  if (graph && !tracker) throw ParamError("graph", "a graph back-end needs a tracker");
  if (graph && graph->dimension() != tracker->dimension())
    throw ParamError("graph", "a " + std::to_string(graph->dimension()) +
                                  "D back-end cannot take the local maps of a " +
                                  std::to_string(tracker->dimension()) + "D tracker");
}

void Pipeline::restoreSession(const std::vector<std::shared_ptr<LocalMap>>& maps,
                              const std::vector<GraphEdge>& edges, bool localize,
                              bool start_known) {
  if (!tracker) throw InputError("restoring a session needs a pipeline with a tracker");
  if (!tracked_->empty() || !local_maps_.empty())
    throw InputError("a session can only be restored before the first frame");
  for (const auto& m : maps)
    if (m->dimension != tracker->dimension())
      throw InputError("the session's maps are " + std::to_string(m->dimension) +
                       "D but the tracker is " + std::to_string(tracker->dimension()) + "D");
  if (graph) graph->restore(maps, edges);
  if (localize && !start_known) {
    if (!graph)
      throw InputError("localization from an unknown start needs a graph back-end with place "
                       "recognition among its loop detectors");
    // Checked now: the localizer that takes over must exist.
    tracker->localizer({maps.begin(), maps.end()});
    searching_in_.assign(maps.begin(), maps.end());
    locked_on_after_ = -1;
    tracker->continueSession(static_cast<int64_t>(maps.size()));
  } else if (localize) {
    tracker.assign(tracker->localizer({maps.begin(), maps.end()}));
  } else {
    tracker->continueSession(static_cast<int64_t>(maps.size()));
  }
  for (const auto& m : maps) local_maps_.emplace(m->id, m);
}

void Pipeline::finish() {
  if (graph) guarded(*graph, [&] { graph->finish(); });
}

RunResult Pipeline::result() const {
  RunResult r;
  if (graph) r.edges = graph->edges();
  for (const auto& [id, map] : local_maps_) r.local_maps.push_back(map);
  // A source gives frames in its log's order with the log's stamps, which may go backwards: a
  // trajectory is written in time order with every stamp as it came, so that evaluation matches
  // each pose to its scan. A repeated stamp keeps its first frame's pose (one pose per time).
  const auto ordered = [](std::vector<StampedPose>& poses) {
    std::stable_sort(poses.begin(), poses.end(),
                     [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });
    poses.erase(std::unique(poses.begin(), poses.end(),
                            [](const StampedPose& a, const StampedPose& b) { return a.t == b.t; }),
                poses.end());
    return Trajectory(std::move(poses));
  };
  std::vector<StampedPose> poses;
  poses.reserve(tracked_->size());
  tracked_->forEach([&](const detail::PoseLog::Entry& f) {
    auto it = local_maps_.find(f.key);
    if (it == local_maps_.end() || !std::isfinite(f.stamp)) return;
    poses.push_back({f.stamp, it->second->origin * f.pose});
  });
  r.trajectory = ordered(poses);
  poses.clear();
  reference_->forEach([&](const detail::PoseLog::Entry& g) {
    if (std::isfinite(g.stamp)) poses.push_back({g.stamp, g.pose});
  });
  r.reference = ordered(poses);
  return r;
}

void Pipeline::throwModuleError(const Configurable& m, const std::string& what) {
  throw ModuleError(m.name(), m.typeName(), what);
}

}  // namespace abi_v1
}  // namespace plugslam
