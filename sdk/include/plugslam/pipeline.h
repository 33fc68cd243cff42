#pragma once
// The processing chain of one run: preprocessors, the tracker, and (issue 5) the graph
// back-end. It knows nothing of how many cues there are.
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/errors.h"
#include "plugslam/frame.h"
#include "plugslam/graph_slam.h"
#include "plugslam/preprocessor.h"
#include "plugslam/sink.h"
#include "plugslam/timings.h"
#include "plugslam/tracker.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {
class PoseLog;
}

/// The core processing chain ("sdk.Pipeline").
class Pipeline : public Configurable {
 public:
  static constexpr const char* kKind = "Pipeline";
  Pipeline();
  ~Pipeline() override;

  SlotList<PreProcessor> preprocessors{this, "preprocessors",
                                       "raw reading -> measurement cue, one per sensor"};
  Slot<Tracker> tracker{this, "tracker", "", "tracks frames against a local map (optional)"};
  Param<std::string> reference{this, "reference", "ground_truth", "",
                               "raw entry (Isometry2d/3d) recorded as the reference trajectory: "
                               "ground truth, or another system's estimate"};
  Slot<GraphBackend> graph{this, "graph", "",
                           "pose graph of local maps, loop closing (optional; needs a tracker)"};
  Param<std::vector<double>> lost_search_spacing{
      this, "lost_search_spacing", {0.25, 0.25}, "m, rad",
      "localization from an unknown start searches the saved maps from the frame's map, then "
      "again once the robot moved or turned this much since (its view changed; each search "
      "covers the whole saved map)"};

  void configure() override;

  /// Runs every stage on one frame. A module's exception is rethrown as ModuleError naming it.
  virtual void process(Frame& frame);
  /// Ends the run: waits for the back-end and applies its last correction.
  virtual void finish();
  /// The run's result so far: trajectory with current corrections, local maps.
  virtual RunResult result() const;
  /// Time spent per module so far.
  Timings& timings() { return timings_; }
  /// Restores a saved session before the first frame: the local maps (ids 0..n-1) and the graph
  /// edges. Mapping (`localize` false) appends new maps after them, joined by loops; localization
  /// tracks against them frozen with the tracker's localizer (Tracker::localizer), which takes
  /// the tracker's place, and adds nothing to the graph. Throws InputError.
  /// With `localize` and not `start_known`, the robot may start anywhere: the mapping tracker
  /// and the graph run (new maps, their own component) until a loop found by place recognition
  /// joins them to the saved maps (the graph's join_by_estimate false), then the localizer
  /// takes over from the pose that join gives; frames before are `lost`.
  void restoreSession(const std::vector<std::shared_ptr<LocalMap>>& maps,
                      const std::vector<GraphEdge>& edges, bool localize,
                      bool start_known = true);
  /// Frames processed before localization from an unknown start locked on (-1: it has not;
  /// 0: the start was known).
  int64_t lockedOnAfter() const { return locked_on_after_; }
  /// The local map `id` the tracker started or the session restored (its scene, its current
  /// origin), nullptr if none. Read it only between frames.
  std::shared_ptr<const LocalMap> findLocalMap(int64_t id) const;

 protected:
  /// Runs `step` as module `m`, timing it and wrapping its exceptions in ModuleError (also
  /// those not derived from std::exception, which a plugin may throw).
  template <class F>
  auto guarded(Configurable& m, F&& step) -> decltype(step()) {
    ScopedTimer timer(timings_, m.name());
    try {
      return step();
    } catch (const ModuleError&) {
      throw;
    } catch (const std::exception& e) {
      throwModuleError(m, e.what());
    } catch (...) {
      throwModuleError(m, "an exception not derived from std::exception");
    }
  }
  [[noreturn]] static void throwModuleError(const Configurable& m, const std::string& what);

  // Every tracked frame (stamp, local map, pose in it), kept to rebuild the trajectory after
  // corrections, and the reference poses; both spill to a temporary file so that memory stays
  // flat on endless runs.
  std::unique_ptr<detail::PoseLog> tracked_;
  std::unique_ptr<detail::PoseLog> reference_;
  std::map<int64_t, std::shared_ptr<LocalMap>> local_maps_;
  // Localization from an unknown start: the saved maps, while not locked on; frames so far.
  std::vector<std::shared_ptr<const LocalMap>> searching_in_;
  int64_t locked_on_after_ = 0, frames_ = 0;
  uint64_t loops_seen_ = 0;  // the graph's loops when its components were last looked at
  // Localization from an unknown start: the pose of the last search, in the run's own frame.
  std::optional<Eigen::Isometry3d> last_search_;

 private:
  // The local map `id` the tracker started (or the session restored); throws ModuleError.
  const LocalMap& localMap(int64_t id) const;
  // Localization from an unknown start: hands over to the localizer once the frame's map is
  // joined to the saved ones, else marks the frame lost.
  void lockOn(Frame& frame);
  Timings timings_;
};

}  // namespace abi_v1
}  // namespace plugslam
