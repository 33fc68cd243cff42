#include "writers/trajectory_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using plugslam::RunResult;
using plugslam::Trajectory;
using plugslam::io::TrajectoryWriter;

namespace {

RunResult sampleResult() {
  RunResult r;
  for (int i = 0; i < 5; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() << i * 0.5, -i * 0.25, 0.0;
    p.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    r.trajectory.push_back(100.0 + i, p);
  }
  return r;
}

// A folder inside this test process's own fresh temporary folder.
std::string outDir(const std::string& name) {
  static const plugslam::testing::TempDir tmp("plugslam_tw");
  const fs::path dir = tmp.path() / name;
  fs::create_directories(dir);
  return dir.string();
}

void expectSame(const Trajectory& a, const Trajectory& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].t, b[i].t, 1e-9);
    EXPECT_TRUE(a[i].pose.isApprox(b[i].pose, 1e-8));
  }
}

TEST(TrajectoryWriter, WritesTumIntoTheOutputFolder) {
  const std::string dir = outDir("tum");
  TrajectoryWriter w;
  w.configure();
  w.begin(dir);
  const RunResult r = sampleResult();
  w.end(r);
  EXPECT_EQ(w.outputPath(), dir + "/trajectory.tum");
  expectSame(r.trajectory, plugslam::readTumTrajectory(dir + "/trajectory.tum"));
  fs::remove_all(dir);
}

TEST(TrajectoryWriter, WritesKittiWithTimes) {
  const std::string dir = outDir("kitti");
  TrajectoryWriter w;
  w.file = std::string("poses.txt");
  w.format = std::string("kitti");
  w.times_file = std::string("times.txt");
  w.configure();
  w.begin(dir);
  const RunResult r = sampleResult();
  w.end(r);
  expectSame(r.trajectory, plugslam::readKittiTrajectory(dir + "/poses.txt", dir + "/times.txt"));
  fs::remove_all(dir);
}

// Item 17.18: plugins/io/README.md's `trajectory: reference` writes the pipeline's reference (and
// `ground_truth`, which the README once named, is refused).
TEST(TrajectoryWriter, WritesTheReferenceWhenAsked) {
  const std::string dir = outDir("reference");
  TrajectoryWriter w;
  EXPECT_THROW(w.trajectory = std::string("ground_truth"), plugslam::ValueError);
  w.trajectory = std::string("reference");
  w.file = std::string("reference.tum");
  w.configure();
  w.begin(dir);
  RunResult r;
  r.reference = sampleResult().trajectory;  // the estimate stays empty
  w.end(r);
  expectSame(r.reference, plugslam::readTumTrajectory(dir + "/reference.tum"));
  fs::remove_all(dir);
}

TEST(TrajectoryWriter, RejectsBadSettings) {
  TrajectoryWriter w;
  EXPECT_THROW(w.format = std::string("csv"), plugslam::ValueError);
  w.times_file = std::string("times.txt");
  EXPECT_THROW(w.configure(), plugslam::ParamError);
}

// Item 17.9: with no `file:`, the name follows the format.
TEST(TrajectoryWriter, DefaultFileNameFollowsTheFormat) {
  const std::string dir = outDir("kitti_default");
  TrajectoryWriter w;
  w.format = std::string("kitti");
  w.configure();
  w.begin(dir);
  const RunResult r = sampleResult();
  w.end(r);
  EXPECT_EQ(w.outputPath(), dir + "/trajectory.kitti");
  EXPECT_FALSE(fs::exists(dir + "/trajectory.tum"));
  // KITTI rows are poses only (no times file here): the poses come back, the stamps do not.
  const Trajectory back = plugslam::readTrajectory(dir + "/trajectory.kitti");
  ASSERT_EQ(back.size(), r.trajectory.size());
  for (size_t i = 0; i < back.size(); ++i)
    EXPECT_TRUE(back[i].pose.isApprox(r.trajectory[i].pose, 1e-8)) << "pose " << i;
  fs::remove_all(dir);
}

// Item 17.11: a run that estimated no pose (no tracker) writes no empty trajectory file.
TEST(TrajectoryWriter, AnEmptyTrajectoryIsNotWritten) {
  const std::string dir = outDir("empty");
  TrajectoryWriter w;
  w.configure();
  w.begin(dir);
  w.end(RunResult{});
  EXPECT_FALSE(fs::exists(dir + "/trajectory.tum"));
  fs::remove_all(dir);
}

TEST(TrajectoryWriter, UnwritableFolderIsAnInputError) {
  TrajectoryWriter w;
  w.configure();
  w.begin("/nonexistent/plugslam/out");
  EXPECT_THROW(w.end(sampleResult()), plugslam::InputError);
}

}  // namespace
