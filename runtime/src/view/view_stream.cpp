#include "view/view_stream.h"

#include <algorithm>
#include <optional>
#include <utility>

#include "plugslam/view/drawers.h"
#include "view/jpeg.h"

namespace plugslam::runtime {

namespace {

// How often the things that change every frame are worth re-sending [s]: status text a person
// reads, the growing current map (it changes a little per frame), the whole graph drawing, the
// growing stretch of trajectory. Far apart enough that their cost disappears into the frames.
constexpr double kStatusPeriod = 0.25;
constexpr double kCurrentMapPeriod = 1.0;
constexpr double kGraphPeriod = 1.0;
constexpr double kSegmentPeriod = 0.2;

std::string mapFrame(int64_t id) { return "map/" + std::to_string(id); }

bool elapsed(std::chrono::steady_clock::time_point& last, double period) {
  const auto now = std::chrono::steady_clock::now();
  if (now - last < std::chrono::duration<double>(period)) return false;
  last = now;
  return true;
}

template <class T>
view::Channel<T>& channelFor(std::map<std::string, view::Channel<T>>& channels,
                             const std::string& topic, view::Latch latch) {
  auto it = channels.find(topic);
  if (it == channels.end()) it = channels.emplace(topic, view::Channel<T>(topic, latch)).first;
  return it->second;
}

view::Color rgba(float r, float g, float b, float a = 1) { return view::Color{r, g, b, a}; }

// The frame of a CameraInfo entry's first camera, and of its rig's second camera.
std::string cameraFrame(const std::string& entry) { return "camera/" + entry; }
std::string secondFrame(const std::string& entry) { return "camera/" + entry + "/second"; }

// The first camera's calibration: its own pinhole and lens, no stereo term in P.
CameraInfo firstCamera(const CameraInfo& info) {
  CameraInfo c;
  c.setIntrinsics(info.intrinsics());
  c.mount = info.mount;
  return c;
}

// The rig's second camera (stereo's right, RGB-D's depth) as a calibration of its own, with its
// pose in the first camera's optical frame: `second` when the source gave it, else, for a
// rectified pair given by its baseline alone, the first camera's pinhole at (baseline, 0, 0).
// A rectified pair's second camera keeps the baseline: P's Tx = -fx baseline (ROS, Foxglove).
std::optional<std::pair<CameraInfo, Eigen::Isometry3d>> secondCamera(const CameraInfo& info) {
  if (!info.second && !(info.baseline > 0)) return std::nullopt;
  CameraInfo c;
  c.setIntrinsics(info.second ? *info.second : info.intrinsics());
  c.baseline = info.baseline;
  Eigen::Isometry3d pose = info.second_pose;
  if (!info.second) pose = Eigen::Translation3d(info.baseline, 0, 0);
  c.mount = info.mount * pose;
  return std::make_pair(c, pose);
}

}  // namespace

ViewStream::ViewStream(uint64_t run) {
  state_.state = "running";
  state_.run = run;
}

void ViewStream::frame(const Frame& frame, const Pipeline& pipeline, uint64_t frames,
                       int64_t total) {
  state_.frame = frames;
  state_.total = total;
  state_.stamp = frame.stamp;
  if (pipeline.tracker) {
    state_.local_maps = pipeline.tracker->stats().local_maps;
    state_.tracking_failures = pipeline.tracker->stats().failed;
  }
  if (pipeline.graph) state_.loops = pipeline.graph->stats().loops_accepted;

  // The robot.
  view::FrameTransforms tf;
  if (frame.estimate.valid) {
    if (pose_.wanted()) pose_.publish(view::PoseInFrame{frame.stamp, "world", frame.estimate.world});
    tf.transforms.push_back(view::FrameTransform{frame.stamp, "world", "base_link",
                                                 frame.estimate.world});
  }
  // Each camera: the first one placed on the robot by its mount, a rig's second one on the
  // first; each calibration once (latched), for the image as viewers get it (shrunk).
  for (const auto& p : frame.raw) {
    if (p.type() != typeid(CameraInfo)) continue;
    const auto& info = static_cast<const Property<CameraInfo>&>(p).value();
    const std::string cam = cameraFrame(p.name());
    tf.transforms.push_back(view::FrameTransform{frame.stamp, "base_link", cam, info.mount});
    const auto second = secondCamera(info);
    if (second)
      tf.transforms.push_back(
          view::FrameTransform{frame.stamp, cam, secondFrame(p.name()), second->second});
    if (!calibrated_[p.name()]) {
      channelFor(calibrations_, "/camera/" + p.name() + "/calibration", view::Latch::kLast)
          .publish(view::CameraCalibration{frame.stamp, cam, viewCalibration(firstCamera(info))});
      if (second)
        channelFor(calibrations_, "/camera/" + p.name() + "/second/calibration",
                   view::Latch::kLast)
            .publish(view::CameraCalibration{frame.stamp, secondFrame(p.name()),
                                             viewCalibration(second->first)});
      calibrated_[p.name()] = true;
    }
  }
  if (!tf.transforms.empty() && tf_.wanted()) tf_.publish(std::move(tf));

  // The trajectory, one stretch per local map in that map's frame: corrections move the map's
  // origin (on /tf/maps), never the stretch.
  if (frame.estimate.valid) {
    if (frame.estimate.local_map != segment_map_) {
      publishSegment();
      segment_.clear();
      segment_map_ = frame.estimate.local_map;
      ++segment_key_;
    }
    segment_.push_back(frame.estimate.in_map);
    segment_stamp_ = frame.stamp;
    if (elapsed(last_segment_, kSegmentPeriod)) publishSegment();
  }

  // The current measurement of every cue that can be drawn, in the robot's frame.
  const auto& drawers = view::Drawers::instance();
  for (const auto& m : frame.measurement) {
    if (!drawers.canDraw(m.type())) continue;
    auto& channel = channelFor(scans_, "/scan/" + m.name(), view::Latch::kNone);
    if (!channel.wanted()) continue;
    view::PointCloud cloud;
    cloud.stamp = frame.stamp;
    cloud.frame = "base_link";
    if (drawers.draw(m, cloud)) channel.publish(std::move(cloud));
  }
  // Camera images as the source gave them. A source names its images (left/right, rgb/depth)
  // apart from the one CameraInfo that calibrates them (raw["camera"]), and writes the first
  // camera's image before the second's: with one CameraInfo, the first image is drawn in the
  // first camera's frame and, when the rig has a second camera, the next one in the second's
  // (a stereo pair's right image at the right camera's pose). Several CameraInfo entries: each
  // image is in the frame of its own name.
  const CameraInfo* info = nullptr;
  std::string info_name;
  int infos = 0;
  for (const auto& p : frame.raw)
    if (p.type() == typeid(CameraInfo) && ++infos == 1) {
      info = &static_cast<const Property<CameraInfo>&>(p).value();
      info_name = p.name();
    }
  const bool has_second = infos == 1 && secondCamera(*info).has_value();
  int images = 0;
  for (const auto& p : frame.raw) {
    if (p.type() != typeid(Image)) continue;
    const int index = images++;
    auto& channel = channelFor(images_, "/camera/" + p.name() + "/image", view::Latch::kNone);
    if (!channel.wanted()) continue;
    const std::string in = infos != 1                    ? cameraFrame(p.name())
                           : (index == 1 && has_second) ? secondFrame(info_name)
                                                        : cameraFrame(info_name);
    // Shrunk to the viewers' size while copied: the frame's image is not ours to keep, and a
    // full-size copy per frame was most of what viewing cost the run.
    channel.publish(view::CameraImage{in, viewImage(static_cast<const Property<Image>&>(p).value())});
  }

  // Local maps: a frame in a new map closes the previous one, which goes out whole, once.
  if (frame.estimate.valid && frame.estimate.local_map >= 0) {
    const int64_t id = frame.estimate.local_map;
    if (id != current_map_) {
      if (current_map_ >= 0 && static_cast<size_t>(current_map_) < maps_.size() &&
          maps_[static_cast<size_t>(current_map_)])
        publishMap(*maps_[static_cast<size_t>(current_map_)]);
      current_map_ = id;
      const auto i = static_cast<size_t>(id);
      if (maps_.size() <= i) {
        maps_.resize(i + 1);
        published_origins_.resize(i + 1, Eigen::Isometry3d::Identity());
        origin_published_.resize(i + 1, false);
      }
      if (!maps_[i]) maps_[i] = pipeline.findLocalMap(id);
      graph_dirty_ = true;
      last_current_map_ = Clock::now();
    } else if (elapsed(last_current_map_, kCurrentMapPeriod)) {
      if (const auto& map = maps_[static_cast<size_t>(id)]) publishMap(*map);
    }
  }
  // The graph and the origins, when the back-end changed something.
  if (pipeline.graph) {
    const GraphStats s = pipeline.graph->stats();
    const uint64_t version = s.optimizations * 1000003ull + s.loops_accepted * 1009ull + s.nodes;
    if (version != graph_version_) graph_dirty_ = true;
    if (graph_dirty_ && elapsed(last_graph_, kGraphPeriod)) {
      graph_version_ = version;
      graph_dirty_ = false;
      publishOrigins(false);
      publishGraph(pipeline);
    }
  } else if (graph_dirty_) {
    graph_dirty_ = false;
    publishOrigins(false);
  }
  publishStatus(false);
}

void ViewStream::publishSegment() {
  if (segment_.empty() || segment_key_ < 0) return;
  trajectory_.publish(view::PosesInFrame{segment_stamp_, mapFrame(segment_map_), segment_},
                      segment_key_);
}

void ViewStream::publishMap(const LocalMap& map) {
  const auto& drawers = view::Drawers::instance();
  for (const auto& entry : map.scene) {
    if (!drawers.canDraw(entry.type())) continue;
    auto& channel = channelFor(map_clouds_, "/map/" + entry.name(), view::Latch::kPerKey);
    view::PointCloud cloud;
    cloud.stamp = map.first_stamp;
    cloud.frame = mapFrame(map.id);
    if (drawers.draw(entry, cloud)) channel.publish(std::move(cloud), map.id);
  }
}

void ViewStream::publishOrigins(bool force) {
  for (size_t i = 0; i < maps_.size(); ++i) {
    if (!maps_[i]) continue;
    const Eigen::Isometry3d& origin = maps_[i]->origin;
    if (!force && origin_published_[i] && origin.isApprox(published_origins_[i], 1e-9) &&
        (origin.translation() - published_origins_[i].translation()).norm() < 1e-6)
      continue;
    published_origins_[i] = origin;
    origin_published_[i] = true;
    view::FrameTransforms t;
    // Stamped with the map's first frame, so a viewer looking transforms up at the stamp of the
    // map's own messages finds the corrected origin.
    t.transforms.push_back(view::FrameTransform{maps_[i]->first_stamp, "world",
                                                mapFrame(static_cast<int64_t>(i)), origin});
    map_tf_.publish(std::move(t), static_cast<int64_t>(i));
  }
}

void ViewStream::publishGraph(const Pipeline& pipeline) {
  if (!graph_.wanted()) return;
  view::SceneEntity odometry, loops;
  odometry.id = "odometry";
  loops.id = "loops";
  odometry.stamp = loops.stamp = state_.stamp;
  view::Lines loop_lines;
  loop_lines.color = rgba(1.0f, 0.35f, 0.2f);
  auto origin = [&](int64_t id) -> const LocalMap* {
    return id >= 0 && static_cast<size_t>(id) < maps_.size() ? maps_[static_cast<size_t>(id)].get()
                                                             : nullptr;
  };
  const std::vector<GraphEdge> edges = pipeline.graph->edges();
  // The odometry of each graph component in its own colour (sessions merged or not yet joined,
  // tracker resets): map 0's blue, the others after it.
  const std::vector<int64_t> components = graphComponents(maps_.size(), edges);
  static const float palette[][3] = {{0.3f, 0.6f, 1.0f}, {0.2f, 0.75f, 0.3f}, {0.65f, 0.45f, 0.9f},
                                     {0.6f, 0.4f, 0.3f}, {0.95f, 0.5f, 0.8f}, {0.1f, 0.8f, 0.85f}};
  std::vector<int64_t> roots;  // components in order of their first map
  std::vector<view::Lines> odo_lines;
  for (const auto& e : edges) {
    const LocalMap* a = origin(e.from);
    const LocalMap* b = origin(e.to);
    if (!a || !b) continue;
    view::Lines* lines = &loop_lines;
    if (!e.loop) {
      const int64_t root = components[static_cast<size_t>(e.from)];
      size_t k = std::find(roots.begin(), roots.end(), root) - roots.begin();
      if (k == roots.size()) {
        roots.push_back(root);
        const float* c = palette[k % (sizeof(palette) / sizeof(palette[0]))];
        odo_lines.emplace_back();
        odo_lines.back().color = rgba(c[0], c[1], c[2]);
      }
      lines = &odo_lines[k];
    }
    lines->points.push_back(a->origin.translation());
    lines->points.push_back(b->origin.translation());
  }
  for (auto& l : odo_lines) odometry.lines.push_back(std::move(l));
  loops.lines.push_back(std::move(loop_lines));
  view::SceneUpdate update;
  update.stamp = state_.stamp;
  update.entities.push_back(std::move(odometry));
  update.entities.push_back(std::move(loops));
  graph_.publish(std::move(update));
}

void ViewStream::publishStatus(bool now) {
  const auto t = Clock::now();
  if (!now && t - last_status_ < std::chrono::duration<double>(kStatusPeriod)) return;
  if (rate_since_ != Clock::time_point{}) {
    const double dt = std::chrono::duration<double>(t - rate_since_).count();
    if (dt > 0 && state_.frame >= rate_frames_)
      state_.hz = state_.state == "running" ? (state_.frame - rate_frames_) / dt : 0.0;
  }
  rate_since_ = t;
  rate_frames_ = state_.frame;
  last_status_ = t;
  status_.publish(state_);
}

void ViewStream::setState(const std::string& state) {
  state_.state = state;
  publishStatus(true);
}

void ViewStream::finished(const RunResult& result, const Pipeline& pipeline) {
  publishSegment();
  for (const auto& m : result.local_maps) {
    if (m->id < 0) continue;
    const auto i = static_cast<size_t>(m->id);
    if (maps_.size() <= i) {
      maps_.resize(i + 1);
      published_origins_.resize(i + 1, Eigen::Isometry3d::Identity());
      origin_published_.resize(i + 1, false);
    }
    maps_[i] = m;
  }
  if (current_map_ >= 0 && static_cast<size_t>(current_map_) < maps_.size() &&
      maps_[static_cast<size_t>(current_map_)])
    publishMap(*maps_[static_cast<size_t>(current_map_)]);
  publishOrigins(false);
  if (pipeline.graph) publishGraph(pipeline);
  state_.state = "finished";
  publishStatus(true);
}

}  // namespace plugslam::runtime
