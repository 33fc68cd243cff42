// Loads the io, sim and odometry plugins through the host, checks their types, and runs a
// pipeline made of them only: the simulator, wheel-odometry prediction and the odometry prior
// slice, with the trajectory written by io.TrajectoryWriter.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "config_builder.h"
#include "host_run.h"
#include "plugin_manager.h"
#include "plugslam/aligner_slice.h"
#include "plugslam/geometry.h"
#include "plugslam/motion_model.h"
#include "plugslam/registry.h"
#include "plugslam/sink.h"
#include "plugslam/source.h"
#include "plugslam/trajectory.h"
#include "run_config.h"
#include "runner.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using namespace plugslam;

namespace {

// `head` (plugins and source) followed by a pipeline of wheel odometry alone
// (tests/support/odometry_only.yaml), its local maps `split_distance` [m] long, writing traj.tum.
std::string odometryOnly(const std::string& head, const std::string& split_distance) {
  std::ifstream in(plugslam::testing::sourceDir() + "/tests/support/odometry_only.yaml");
  std::stringstream pipeline;
  pipeline << in.rdbuf();
  std::string text = pipeline.str();
  const std::string split = "distance: 1.0";
  text.replace(text.find(split), split.size(), "distance: " + split_distance);
  return head + text + "outputs:\n  - {type: io.TrajectoryWriter, file: traj.tum, format: tum}\n";
}

std::string runText(const std::string& noise) {
  std::string text = odometryOnly(
      "plugins: [sim, io, odometry]\n"
      "source: {type: sim.Simulator2D, session: stage-0, lasers: [front_laser], "
      "odometry_noise: NOISE}\n",
      "1.0");
  text.replace(text.find("NOISE"), 5, noise);
  return text;
}

TEST(IoOdometryPlugins, RegisterTheirTypes) {
  runtime::PluginManager plugins;
  plugins.load("io");
  plugins.load("sim");
  plugins.load("odometry");
  const std::pair<const char*, const char*> expected[] = {
      {"io.CarmenSource", Source::kKind},
      {"io.RosbagSource", Source::kKind},
      {"sim.Simulator2D", Source::kKind},
      {"io.TrajectoryWriter", Sink::kKind},
      {"odometry.WheelOdometry", MotionModel<Space2D>::kKind},
      {"odometry.PriorSlice", AlignerSlice<Space2D>::kKind}};
  for (const auto& [name, kind] : expected) {
    auto info = Registry::instance().find(name);
    ASSERT_TRUE(info.has_value()) << name;
    EXPECT_EQ(info->kind, kind) << name;
    EXPECT_FALSE(info->doc.empty()) << name;
    EXPECT_NE(Registry::instance().create(name), nullptr) << name;
  }
}

// Perfect odometry through WheelOdometry + PriorSlice reproduces the true path.
TEST(IoOdometryPlugins, OdometryOnlyRunFollowsGroundTruth) {
  const plugslam::testing::TempDir tmp("plugslam_ioodom");
  const fs::path out = tmp.path() / "out";
  runtime::PluginManager plugins;  // keeps sim loaded for the ground truth below
  const auto report = plugslam::testing::runDocument(
      runtime::loadConfigText(runText("0.0"), "run.yaml"), out.string(), &plugins);
  ASSERT_GT(report.frames, 100u);
  const Trajectory traj = readTumTrajectory((out / "traj.tum").string());
  ASSERT_EQ(traj.size(), report.frames);

  // The ground truth from a second simulator with the same settings.
  auto truth = std::dynamic_pointer_cast<Source>(Registry::instance().create("sim.Simulator2D"));
  ASSERT_TRUE(truth);
  auto* session = dynamic_cast<Param<std::string>*>(truth->findParam("session"));
  ASSERT_NE(session, nullptr);
  session->set("stage-0");
  truth->configure();
  Frame f;
  Eigen::Isometry2d first = Eigen::Isometry2d::Identity();
  double worst = 0;
  for (size_t i = 0; truth->next(f); ++i) {
    ASSERT_LT(i, traj.size());
    const auto& gt = f.raw.get<Eigen::Isometry2d>("ground_truth");
    if (i == 0) first = gt;
    const Eigen::Isometry2d expected = first.inverse() * gt;  // the run starts at the origin
    const Eigen::Isometry2d got = Space2D::from3D(traj[i].pose);
    worst = std::max(worst, (expected.translation() - got.translation()).norm());
    EXPECT_NEAR(traj[i].t, f.stamp, 1e-9);
  }
  EXPECT_LT(worst, 1e-6) << "perfect odometry must give the true path";
  EXPECT_TRUE(fs::exists(out / "run.json"));
  fs::remove_all(out);
}

// A raw CARMEN log whose stamps go backwards once and which has no ODOM lines: the run tracks on
// the laser lines' odometry, and the written trajectory holds every scan at the log's own stamp
// (printed to the nanosecond, so a relation names it exactly), in time order.
TEST(IoOdometryPlugins, CarmenRunKeepsTheLogsStamps) {
  const plugslam::testing::TempDir tmp("plugslam_ioodom_stamps");
  const std::string log = tmp.write("raw.clf",
                                    "FLASER 3 1 2 3 0 0 0 0 0 0 976052857.337284 h 0.1\n"
                                    "FLASER 3 1 2 3 1 0 0 1 0 0 976052857.537911 h 0.3\n"
                                    "FLASER 3 1 2 3 2 0 0 2 0 0 976052857.437000 h 0.4\n"
                                    "FLASER 3 1 2 3 3 0 0 3 0 0 976052857.737502 h 0.5\n"
                                    "FLASER 3 1 2 3 4 0 0 4 0 0 976052857.837503 h 0.6\n");
  std::string text =
      odometryOnly("plugins: [io, odometry]\nsource: {type: io.CarmenSource, path: LOG}\n", "1.5");
  text.replace(text.find("LOG"), 3, log);
  const fs::path out = tmp.path() / "out";
  const auto report =
      plugslam::testing::runDocument(runtime::loadConfigText(text, "run.yaml"), out.string());
  ASSERT_EQ(report.frames, 5u);
  EXPECT_FALSE(fs::exists(out / "reference.tum")) << "a raw log's poses are no reference";
  const Trajectory traj = readTumTrajectory((out / "traj.tum").string());
  ASSERT_EQ(traj.size(), 5u);
  // Time order; the scan logged third (x = 2) was stamped before the second (x = 1).
  const double stamps[5] = {976052857.337284, 976052857.437000, 976052857.537911, 976052857.737502,
                            976052857.837503};
  const double xs[5] = {0, 2, 1, 3, 4};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(traj[i].t, stamps[i]) << i;  // bit for bit, through the TUM file
    EXPECT_NEAR(traj[i].pose.translation().x(), xs[i], 1e-6) << i;
  }
}

}  // namespace
