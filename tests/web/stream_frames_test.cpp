// Where the viewer stream puts things, composed the way Foxglove, Lichtblick and the built-in
// page compose it: a local map's cloud and its stretch of trajectory are in frame map/<id>, that
// frame is placed in the world by /tf/maps (world -> map/<id>, the map's corrected origin), the
// robot by /tf (world -> base_link), the current scan is in base_link. A run of the simulated
// office (sim2d_double_laser.yaml, the built-in default) is recorded message by message; the
// latched state a viewer ends up with must put the last scan on the walls the earlier local maps
// hold, and the trajectory's end where the run's own (corrected) trajectory ends. The page once
// ignored /tf/maps and drew every local map at the world origin; the check below also measures
// what that costs.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/view/publisher.h"
#include "run_config.h"
#include "runner.h"
#include "sim_worlds.h"
#include "temp_dir.h"
#include "test_paths.h"
#include "view/view_json.h"
#include "view/view_stream.h"

using namespace plugslam;
using namespace plugslam::runtime;

namespace {

// Keeps what a late viewer gets: the last message of each topic and key.
class Recorder : public view::Publisher {
 public:
  int declare(const std::string& topic, size_t, view::Latch) override {
    for (size_t i = 0; i < topics_.size(); ++i)
      if (topics_[i] == topic) return static_cast<int>(i);
    topics_.push_back(topic);
    return static_cast<int>(topics_.size() - 1);
  }
  bool wants(int) override { return true; }
  void publish(int channel, view::Drawable&& message, int64_t key) override {
    last_[{topics_[static_cast<size_t>(channel)], key}] = std::move(message);
  }
  // The last message of each key of `topic`, by key.
  template <class T>
  std::map<int64_t, T> of(const std::string& topic) const {
    std::map<int64_t, T> out;
    for (const auto& [id, message] : last_)
      if (id.first == topic && std::holds_alternative<T>(message))
        out[id.second] = std::get<T>(message);
    return out;
  }

 private:
  std::vector<std::string> topics_;
  std::map<std::pair<std::string, int64_t>, view::Drawable> last_;
};

struct StreamObserver : RunObserver {
  ViewStream stream;
  RunResult result;
  void frame(const Frame& f, Pipeline& p, uint64_t frames, int64_t total) override {
    stream.frame(f, p, frames, total);
  }
  void finished(const RunResult& r, Pipeline& p) override {
    stream.finished(r, p);
    result = r;
  }
};

// Cells of `cell` metres holding at least one of `points`.
struct CellSet {
  double cell;
  std::set<std::pair<long, long>> cells;
  std::pair<long, long> key(const Eigen::Vector3d& p) const {
    return {static_cast<long>(std::floor(p.x() / cell)), static_cast<long>(std::floor(p.y() / cell))};
  }
  void add(const Eigen::Vector3d& p) { cells.insert(key(p)); }
  // A point within one cell of a held one.
  bool near(const Eigen::Vector3d& p) const {
    const auto [x, y] = key(p);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        if (cells.count({x + dx, y + dy})) return true;
    return false;
  }
};

TEST(StreamFrames, ComposedLikeAViewerTheScanLiesOnTheMapsAndTheTrajectoryEndsWhereTheRunDoes) {
  plugslam::testing::TempDir dir("plugslam_stream_frames");
  PluginManager plugins;
  ConfigDocument doc =
      loadConfigFile(plugslam::testing::sourceDir() + "/configs/sim2d_double_laser.yaml");
  // 400 frames of the office: a dozen local maps, the last scan seeing walls the earlier ones hold.
  applyOverride(doc, "max_frames=400");
  auto run = buildRun(doc, plugins);

  Recorder recorder;
  view::installPublisher(&recorder);
  StreamObserver observer;
  RunOptions options;
  options.out_dir = dir.file("out");
  options.observer = &observer;
  const RunReport report = runPipeline(*run, options);
  view::installPublisher(nullptr);
  ASSERT_EQ(report.frames, 400u);
  ASSERT_GE(observer.result.local_maps.size(), 4u);

  // Every local map's frame is placed in the world by /tf/maps, at the map's final origin.
  std::map<std::string, Eigen::Isometry3d> world_of;
  for (const auto& [key, tf] : recorder.of<view::FrameTransforms>("/tf/maps"))
    for (const auto& t : tf.transforms) {
      EXPECT_EQ(t.parent, "world");
      EXPECT_EQ(t.child, "map/" + std::to_string(key));
      world_of[t.child] = t.transform;
    }
  for (const auto& m : observer.result.local_maps) {
    const std::string frame = "map/" + std::to_string(m->id);
    ASSERT_TRUE(world_of.count(frame)) << frame << " has no transform on /tf/maps";
    EXPECT_TRUE(world_of[frame].isApprox(m->origin, 1e-9)) << frame << " is not at its origin";
  }

  // The maps' clouds in world coordinates, the last map (the one the scan was merged into) apart.
  const auto clouds = recorder.of<view::PointCloud>("/map/front");
  ASSERT_EQ(clouds.size(), observer.result.local_maps.size());
  const int64_t last = observer.result.local_maps.back()->id;
  CellSet composed{0.1, {}}, unplaced{0.1, {}};
  for (const auto& [key, cloud] : clouds) {
    ASSERT_EQ(cloud.frame, "map/" + std::to_string(key));
    if (key == last) continue;
    for (const auto& p : cloud.points) {
      const Eigen::Vector3d in_map = cloud.pose * p.cast<double>();
      composed.add(world_of[cloud.frame] * in_map);
      unplaced.add(in_map);  // the old page: the map frame unknown, taken as the world
    }
  }

  // The last scan, placed by the robot's last /tf.
  const auto tf = recorder.of<view::FrameTransforms>("/tf");
  ASSERT_EQ(tf.size(), 1u);
  Eigen::Isometry3d robot = Eigen::Isometry3d::Identity();
  bool found = false;
  for (const auto& t : tf.begin()->second.transforms)
    if (t.parent == "world" && t.child == "base_link") {
      robot = t.transform;
      found = true;
    }
  ASSERT_TRUE(found) << "no world -> base_link on /tf";
  const auto scans = recorder.of<view::PointCloud>("/scan/front");
  ASSERT_EQ(scans.size(), 1u);
  const view::PointCloud& scan = scans.begin()->second;
  ASSERT_EQ(scan.frame, "base_link");
  ASSERT_GT(scan.points.size(), 50u);
  size_t on_map = 0, on_unplaced = 0;
  for (const auto& p : scan.points) {
    const Eigen::Vector3d w = robot * (scan.pose * p.cast<double>());
    on_map += composed.near(w);
    on_unplaced += unplaced.near(w);
  }
  const double fraction = double(on_map) / scan.points.size();
  const double unplaced_fraction = double(on_unplaced) / scan.points.size();
  std::printf("last scan on the earlier maps: %.1f %% composed, %.1f %% without /tf/maps\n",
              100 * fraction, 100 * unplaced_fraction);
  // Within 0.1-0.2 m (one cell and its neighbours): the simulator's range noise and the maps'
  // 5 cm voxels stay well inside. Measured 82.4 % composed, 9.4 % without /tf/maps (2026-12-02);
  // the bounds leave ~12 points either way for the loop closer's timing, and still tell the two
  // apart by far.
  EXPECT_GE(fraction, 0.7);
  EXPECT_LT(unplaced_fraction, 0.3);

  // The trajectory's last stretch, in its map's frame, ends where the run's corrected trajectory
  // ends.
  const auto stretches = recorder.of<view::PosesInFrame>("/trajectory");
  ASSERT_FALSE(stretches.empty());
  const view::PosesInFrame& stretch = stretches.rbegin()->second;
  ASSERT_TRUE(world_of.count(stretch.frame)) << stretch.frame;
  ASSERT_FALSE(stretch.poses.empty());
  ASSERT_FALSE(observer.result.trajectory.empty());
  const Eigen::Isometry3d end = world_of[stretch.frame] * stretch.poses.back();
  const Eigen::Isometry3d expected = observer.result.trajectory.poses().back().pose;
  EXPECT_LT((end.translation() - expected.translation()).norm(), 1e-6);
}

// A stereo rig as a source gives it (KITTI-like: a rectified pair 0.537 m apart, images 1241 px
// wide, shrunk 2x for viewers): raw "left", "right" (Images, the first camera's first) and
// "camera" (the CameraInfo, with its `second` camera). Composed like a viewer, the right image
// sits at the right camera's pose, and each camera has its calibration for the image as sent.
CameraInfo kittiLikeRig() {
  CameraInfo c;
  c.setIntrinsics(CameraIntrinsics{718.856, 718.856, 607.1928, 185.2157, 1241, 376, Distortion{}});
  c.baseline = 0.537;
  // Optical frame (x right, y down, z forward) on a robot (x forward, z up), 1.65 m up.
  Eigen::Matrix3d r;
  r << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  c.mount.linear() = r;
  c.mount.translation() = Eigen::Vector3d(0.2, 0, 1.65);
  c.second = c.intrinsics();
  c.second_pose = Eigen::Translation3d(0.537, 0, 0);
  return c;
}

Image grey(int w, int h) {
  Image im;
  im.resize(w, h, 1);
  return im;
}

// The recorded frames: frame transforms by child, images by topic, calibrations by topic.
struct CameraFrames {
  std::map<std::string, view::FrameTransform> tf;
  std::map<std::string, view::CameraImage> images;
  std::map<std::string, view::CameraCalibration> calibrations;
  // `child` in `root` through the parents /tf gives.
  Eigen::Isometry3d in(const std::string& root, std::string child) const {
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    while (child != root) {
      const auto it = tf.find(child);
      if (it == tf.end()) {
        ADD_FAILURE() << "/tf does not place " << child;
        return out;
      }
      out = it->second.transform * out;
      child = it->second.parent;
    }
    return out;
  }
};

CameraFrames streamCameraFrame(const CameraInfo& info, int images) {
  Recorder recorder;
  view::installPublisher(&recorder);
  {
    ViewStream stream;
    Pipeline pipeline;
    Frame frame;
    frame.stamp = 1.5;
    const char* names[] = {"left", "right"};
    for (int i = 0; i < images; ++i)
      frame.raw.set<Image>(names[i], grey(i == 0 ? info.width : info.second->width,
                                           i == 0 ? info.height : info.second->height));
    frame.raw.set<CameraInfo>("camera", info);
    stream.frame(frame, pipeline, 1, -1);
  }
  view::installPublisher(nullptr);
  CameraFrames out;
  for (const auto& [key, message] : recorder.of<view::FrameTransforms>("/tf"))
    for (const auto& t : message.transforms) out.tf[t.child] = t;
  for (const char* topic : {"/camera/left/image", "/camera/right/image"})
    for (const auto& [key, m] : recorder.of<view::CameraImage>(topic)) out.images[topic] = m;
  for (const char* topic : {"/camera/camera/calibration", "/camera/camera/second/calibration"})
    for (const auto& [key, m] : recorder.of<view::CameraCalibration>(topic))
      out.calibrations[topic] = m;
  return out;
}

TEST(StreamFrames, AStereoPairsRightImageIsAtTheRightCameraAndEachCameraIsCalibrated) {
  const CameraInfo rig = kittiLikeRig();
  const CameraFrames f = streamCameraFrame(rig, 2);
  ASSERT_EQ(f.images.size(), 2u);
  ASSERT_EQ(f.calibrations.size(), 2u);
  const auto& left = f.images.at("/camera/left/image");
  const auto& right = f.images.at("/camera/right/image");
  EXPECT_NE(left.frame, right.frame);
  // Composed from base_link: the left image at the mount, the right one at the mount moved by
  // the baseline along the left camera's x axis (to the robot's right, -y), both looking ahead.
  const Eigen::Isometry3d l = f.in("base_link", left.frame), r = f.in("base_link", right.frame);
  EXPECT_TRUE(l.isApprox(rig.mount, 1e-12));
  EXPECT_TRUE(r.isApprox(rig.mount * rig.second_pose, 1e-12));
  EXPECT_TRUE((r.translation() - Eigen::Vector3d(0.2, -0.537, 1.65)).isZero(1e-12));
  EXPECT_TRUE(r.linear().isApprox(l.linear(), 1e-12));

  // One calibration per camera, each in its image's frame and for the image as sent (1241 px
  // averaged 2x: 620 px; pixel x' is the mean of source pixels 2x' and 2x' + 1).
  const auto& first = f.calibrations.at("/camera/camera/calibration");
  const auto& second = f.calibrations.at("/camera/camera/second/calibration");
  EXPECT_EQ(first.frame, left.frame);
  EXPECT_EQ(second.frame, right.frame);
  for (const auto* c : {&first, &second}) {
    EXPECT_EQ(c->info.width, 620);
    EXPECT_EQ(c->info.height, 188);
    EXPECT_DOUBLE_EQ(c->info.fx, 718.856 / 2);
    EXPECT_DOUBLE_EQ(c->info.cx, (607.1928 - 0.5) / 2);
  }
  // On the wire (ROS's and Foxglove's convention): the right camera of a rectified pair has
  // P's Tx = -fx baseline, the left one 0.
  const auto p = [](const view::CameraCalibration& c) {
    return nlohmann::json::parse(encodeJson(view::Drawable{c})).at("P");
  };
  EXPECT_DOUBLE_EQ(p(first)[3].get<double>(), 0.0);
  EXPECT_NEAR(p(second)[3].get<double>(), -718.856 / 2 * 0.537, 1e-9);
}

TEST(StreamFrames, AnUnrectifiedPairsSecondCameraHasItsOwnLensAndPose) {
  // EuRoC-like: the second camera has its own pinhole and distortion and sits 11 cm to the right,
  // a little turned; no rectified baseline.
  CameraInfo rig = kittiLikeRig();
  rig.width = 752;
  rig.height = 480;
  rig.baseline = 0;
  rig.distortion = Distortion{Distortion::Model::kRadialTangential, {-0.28, 0.07, 2e-4, 2e-5}};
  rig.second = CameraIntrinsics{457.6, 456.1, 379.9, 255.2, 752, 480,
                                Distortion{Distortion::Model::kRadialTangential,
                                           {-0.28, 0.07, -1e-4, -2e-5}}};
  rig.second_pose = Eigen::Translation3d(0.11, 0, 0) * Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitY());
  const CameraFrames f = streamCameraFrame(rig, 2);
  ASSERT_EQ(f.images.size(), 2u);
  ASSERT_EQ(f.calibrations.size(), 2u);
  EXPECT_TRUE(f.in("base_link", f.images.at("/camera/right/image").frame)
                  .isApprox(rig.mount * rig.second_pose, 1e-12));
  const auto& second = f.calibrations.at("/camera/camera/second/calibration");
  // 752 px: shrunk 2x.
  EXPECT_DOUBLE_EQ(second.info.fx, 457.6 / 2);
  EXPECT_EQ(second.info.distortion.coefficients, rig.second->distortion.coefficients);
  const auto wire = nlohmann::json::parse(encodeJson(view::Drawable{second}));
  EXPECT_EQ(wire.at("distortion_model").get<std::string>(), "plumb_bob");
  EXPECT_DOUBLE_EQ(wire.at("P")[3].get<double>(), 0.0);  // not rectified: no stereo term
}

TEST(StreamFrames, AMonoCameraHasOneFrameAndOneCalibration) {
  CameraInfo mono = kittiLikeRig();
  mono.baseline = 0;
  mono.second.reset();
  mono.width = 640;
  mono.height = 480;
  const CameraFrames f = streamCameraFrame(mono, 1);
  ASSERT_EQ(f.images.size(), 1u);
  EXPECT_EQ(f.images.begin()->second.frame, "camera/camera");
  ASSERT_EQ(f.calibrations.size(), 1u);
  EXPECT_EQ(f.calibrations.begin()->second.info.width, 640);  // not shrunk
  EXPECT_EQ(f.tf.count("camera/camera/second"), 0u);
}

}  // namespace


TEST(StreamFrames, TheGraphDrawsEachComponentInItsOwnColour) {
  // A run of another building on a restored session of the office, started anywhere: place
  // recognition finds nothing to join, so the graph has two components.
  plugslam::testing::TempDir dir("plugslam_stream_components");
  PluginManager plugins;
  const auto office = [&](const std::vector<std::string>& sets) {
    ConfigDocument doc =
        loadConfigFile(plugslam::testing::sourceDir() + "/configs/sim2d_single_laser.yaml");
    for (const std::string& s : {std::string("outputs=[]"), std::string("max_frames=150"),
                                 std::string("pipeline.graph.deterministic=true"),
                                 std::string("pipeline.graph.join_by_estimate=false")})
      applyOverride(doc, s);
    for (const auto& s : sets) applyOverride(doc, s);
    return buildRun(doc, plugins);
  };
  auto first = office({});
  RunOptions options;
  options.out_dir = dir.file("first");
  runPipeline(*first, options);
  const RunResult saved = first->pipeline->result();
  std::vector<std::shared_ptr<LocalMap>> maps;
  for (const auto& m : saved.local_maps) maps.push_back(std::make_shared<LocalMap>(*m));

  plugslam::testing::writeSevenSidedHall(dir.file("hall.txt"));
  auto second = office({"source.world=" + dir.file("hall.txt"), "source.start=[0, 0]"});
  second->pipeline->restoreSession(maps, saved.edges, false);
  Recorder recorder;
  view::installPublisher(&recorder);
  StreamObserver observer;
  options.out_dir = dir.file("second");
  options.observer = &observer;
  const RunReport report = runPipeline(*second, options);
  view::installPublisher(nullptr);
  ASSERT_EQ(report.graph_components.size(), 2u) << "the hall was joined to the office";

  const auto graph = recorder.of<view::SceneUpdate>("/graph");
  ASSERT_EQ(graph.size(), 1u);
  const view::SceneEntity* odometry = nullptr;
  for (const auto& e : graph.begin()->second.entities)
    if (e.id == "odometry") odometry = &e;
  ASSERT_NE(odometry, nullptr);
  ASSERT_EQ(odometry->lines.size(), 2u) << "one set of lines per component";
  const auto& a = odometry->lines[0].color;
  const auto& b = odometry->lines[1].color;
  EXPECT_TRUE(a.r != b.r || a.g != b.g || a.b != b.b) << "the components share a colour";
  // Each component's lines join its own maps: the office's first, then the hall's.
  const size_t office_maps = saved.local_maps.size();
  EXPECT_EQ(odometry->lines[0].points.size(), 2 * (office_maps - 1));
  EXPECT_EQ(odometry->lines[1].points.size(),
            2 * (observer.result.local_maps.size() - office_maps - 1));
}
