#pragma once
// What a run shows by itself: after each frame, the robot's pose and the frame transforms, the
// trajectory (one stretch per local map, in the map's frame), every measurement cue and every
// local map that has a drawer, the pose graph with its loops apart, camera images and status. The
// map goes out in increments: a local map once when it closes (and at most every second while it
// grows); a correction of the graph re-sends only the map origins that moved. Everything goes
// through view::Channel, so with no receiver it costs the checks and nothing else.
#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/frame.h"
#include "plugslam/pipeline.h"
#include "plugslam/view/publisher.h"

namespace plugslam::runtime {

/// The run's own drawables, published from the pipeline's thread.
class ViewStream {
 public:
  /// A stream for run number `run` of the host (see view::Status::run).
  explicit ViewStream(uint64_t run = 1);
  /// After each processed frame: `frames` so far of `total` (-1: unknown).
  void frame(const Frame& frame, const Pipeline& pipeline, uint64_t frames, int64_t total);
  /// The run's state changed ("running", "paused", "finished", "idle"): status goes out now.
  void setState(const std::string& state);
  /// The run ended: the last local map, every corrected origin, the final graph and status.
  void finished(const RunResult& result, const Pipeline& pipeline);

 private:
  using Clock = std::chrono::steady_clock;
  void publishStatus(bool now);
  void publishMap(const LocalMap& map);
  void publishOrigins(bool force);
  void publishGraph(const Pipeline& pipeline);
  void publishSegment();

  view::Channel<view::Status> status_{"/status", view::Latch::kLast};
  view::Channel<view::PoseInFrame> pose_{"/pose", view::Latch::kLast};
  view::Channel<view::FrameTransforms> tf_{"/tf", view::Latch::kLast};
  view::Channel<view::FrameTransforms> map_tf_{"/tf/maps", view::Latch::kPerKey};
  view::Channel<view::PosesInFrame> trajectory_{"/trajectory", view::Latch::kPerKey};
  view::Channel<view::SceneUpdate> graph_{"/graph", view::Latch::kLast};
  std::map<std::string, view::Channel<view::PointCloud>> scans_, map_clouds_;
  std::map<std::string, view::Channel<view::CameraImage>> images_;
  std::map<std::string, view::Channel<view::CameraCalibration>> calibrations_;

  view::Status state_;
  Clock::time_point last_status_{}, last_current_map_{}, last_graph_{}, last_segment_{};
  Clock::time_point rate_since_{};
  uint64_t rate_frames_ = 0;
  // Local maps seen so far, by id, and the origin each was last published at.
  std::vector<std::shared_ptr<const LocalMap>> maps_;
  std::vector<Eigen::Isometry3d> published_origins_;
  std::vector<bool> origin_published_;
  int64_t current_map_ = -1;
  uint64_t graph_version_ = ~0ull;  // optimizations + loops + nodes when the graph was drawn
  bool graph_dirty_ = false;
  // The stretch of trajectory in the current local map.
  int64_t segment_map_ = -1;
  int64_t segment_key_ = -1;
  double segment_stamp_ = 0;
  std::vector<Eigen::Isometry3d> segment_;
  std::map<std::string, bool> calibrated_;  // camera infos published
};

}  // namespace plugslam::runtime
