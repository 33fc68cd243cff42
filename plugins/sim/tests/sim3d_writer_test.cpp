// Rendered frames written in the KITTI and TUM RGB-D layouts by the io writers, read back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "images/png.h"
#include "plugslam/errors.h"
#include "plugslam/trajectory.h"
#include "sim3d/simulator.h"
#include "simulator3d_source.h"
#include "writers/image_sequence_writer.h"
#include "writers/sequence_writers.h"
#include "temp_dir.h"

namespace plugslam::sim::sim3d {
namespace {

namespace fs = std::filesystem;

// A path (not created) inside this test process's own fresh temporary folder.
fs::path tempDir(const std::string& name) {
  static const plugslam::testing::TempDir tmp("plugslam_sim3d");
  fs::path p = tmp.path() / name;
  fs::remove_all(p);
  return p;
}

// Renders frames [0, n) and writes them with the io plugin's KITTI writer.
void writeKittiSequence(const Simulator3D& sim, const std::string& dir, size_t n) {
  io::KittiWriter writer(dir, sim.cameraInfo());
  Sim3DFrame f;
  for (size_t k = 0; k < n; ++k) {
    sim.render(k, &f);
    writer.add(f.stamp, f.left, f.right, f.pose);
  }
  writer.finish();
}

// Renders frames [0, n) and writes them with the io plugin's TUM RGB-D writer.
void writeTumSequence(const Simulator3D& sim, const std::string& dir, size_t n) {
  io::TumWriter writer(dir);
  Sim3DFrame f;
  for (size_t k = 0; k < n; ++k) {
    sim.render(k, &f);
    writer.add(f.stamp, f.left, f.depth, f.pose);
  }
  writer.finish();
}

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

TEST(Sim3DWriter, TumLayoutReadsBack) {
  ScenarioOptions o;
  o.duration = 1.0;
  const Simulator3D sim = Simulator3D::fromOptions(o);
  const fs::path dir = tempDir("tum");
  writeTumSequence(sim, dir.string(), 3);
  for (const char* f : {"rgb.txt", "depth.txt", "groundtruth.txt"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const auto rgb_lines = lines(dir / "rgb.txt");
  ASSERT_EQ(rgb_lines.size(), 6u);  // 3 comment lines + 3 frames
  EXPECT_EQ(rgb_lines[3], "0.000000 rgb/0.000000.png");
  Sim3DFrame f;
  sim.render(1, &f);
  const std::string name = rgb_lines[4].substr(rgb_lines[4].find(' ') + 1);
  const io::PngImage rgb = io::readPng((dir / name).string());
  EXPECT_EQ(rgb.width, 640);
  EXPECT_EQ(rgb.height, 480);
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(rgb.bit_depth, 8);
  for (size_t i = 0; i < f.left.data.size(); ++i) ASSERT_EQ(rgb.samples[i], f.left.data[i]);
  const auto depth_lines = lines(dir / "depth.txt");
  const io::PngImage depth =
      io::readPng((dir / depth_lines[4].substr(depth_lines[4].find(' ') + 1)).string());
  EXPECT_EQ(depth.channels, 1);
  EXPECT_EQ(depth.bit_depth, 16);
  ASSERT_EQ(depth.samples.size(), f.depth.data.size());
  size_t valid = 0;
  for (size_t i = 0; i < depth.samples.size(); ++i) {
    ASSERT_EQ(depth.samples[i], static_cast<uint16_t>(std::lround(f.depth.data[i] * 5000.0)));
    valid += depth.samples[i] > 0;
  }
  EXPECT_GT(valid, depth.samples.size() / 2);
  const Trajectory gt = readTrajectory((dir / "groundtruth.txt").string(), TrajectoryFormat::Tum);
  ASSERT_EQ(gt.size(), 3u);
  EXPECT_TRUE(gt[1].pose.isApprox(f.pose, 1e-6));
  EXPECT_NEAR(gt[1].t, f.stamp, 1e-6);
  fs::remove_all(dir);
}

TEST(Sim3DWriter, KittiLayoutReadsBack) {
  ScenarioOptions o;
  o.world = "street";
  o.rig = Rig::kStereo;
  const Simulator3D sim = Simulator3D::fromOptions(o);
  const fs::path dir = tempDir("kitti");
  writeKittiSequence(sim, dir.string(), 3);
  for (const char* f :
       {"calib.txt", "times.txt", "poses/00.txt", "image_0/000000.png", "image_1/000002.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const io::PngImage left = io::readPng((dir / "image_0" / "000002.png").string());
  EXPECT_EQ(left.width, 1241);
  EXPECT_EQ(left.height, 376);
  EXPECT_EQ(left.channels, 1);
  EXPECT_EQ(left.bit_depth, 8);
  Sim3DFrame f;
  sim.render(2, &f);
  for (size_t i = 0; i < f.left.data.size(); ++i) ASSERT_EQ(left.samples[i], f.left.data[i]);
  const io::PngImage right = io::readPng((dir / "image_1" / "000002.png").string());
  for (size_t i = 0; i < f.right.data.size(); ++i) ASSERT_EQ(right.samples[i], f.right.data[i]);
  // calib.txt: P1 carries -fx * baseline.
  const auto calib = lines(dir / "calib.txt");
  ASSERT_GE(calib.size(), 5u);
  std::istringstream p1(calib[1].substr(4));
  double v[12];
  for (double& x : v) p1 >> x;
  EXPECT_NEAR(v[3], -718.856 * 0.54, 1e-3);
  EXPECT_NEAR(v[0], 718.856, 1e-6);
  const auto times = lines(dir / "times.txt");
  ASSERT_EQ(times.size(), 3u);
  EXPECT_NEAR(std::stod(times[1]), 0.1, 1e-9);
  const Trajectory poses =
      readTrajectory((dir / "poses" / "00.txt").string(), TrajectoryFormat::Kitti);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_TRUE(poses[0].pose.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
  Sim3DFrame f0;
  sim.render(0, &f0);
  EXPECT_TRUE(poses[2].pose.isApprox(f0.pose.inverse() * f.pose, 1e-6));
  fs::remove_all(dir);
}

TEST(Sim3DWriter, ImageSequenceWriterSinkWritesWhatTheSourceEmits) {
  const fs::path out = tempDir("sink");
  for (const char* layout : {"tum", "kitti"}) {
    Simulator3DSource source;
    const bool kitti = std::string(layout) == "kitti";
    if (kitti) {
      source.world = std::string("street");
      source.camera = std::string("stereo");
    } else {
      source.duration = 0.1;
    }
    source.configure();
    io::ImageSequenceWriter sink;
    sink.layout = std::string(layout);
    sink.folder = std::string(layout);
    sink.configure();
    sink.begin(out.string());
    Frame f;
    for (int k = 0; k < 3 && source.next(f); ++k) sink.consume(f);
    sink.end(RunResult{});
    if (kitti) {
      EXPECT_TRUE(fs::exists(out / "kitti" / "image_1" / "000002.png"));
      EXPECT_EQ(lines(out / "kitti" / "poses" / "00.txt").size(), 3u);
    } else {
      EXPECT_EQ(lines(out / "tum" / "groundtruth.txt").size(), 4u);  // header + 3 poses
      EXPECT_EQ(io::readPng((out / "tum" / "depth" / "0.000000.png").string()).bit_depth, 16);
    }
  }
  // A frame without images is refused with a message.
  io::ImageSequenceWriter sink;
  sink.configure();
  sink.begin(out.string());
  Frame empty;
  empty.raw.set<Eigen::Isometry3d>("ground_truth", Eigen::Isometry3d::Identity());
  EXPECT_THROW(sink.consume(empty), InputError);
  fs::remove_all(out);
}

}  // namespace
}  // namespace plugslam::sim::sim3d
