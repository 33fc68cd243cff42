// Loads the io, sim and odometry plugins through the host, checks their types, and runs a
// pipeline made of them only: the simulator, wheel-odometry prediction and the odometry prior
// slice, with the trajectory written by io.TrajectoryWriter.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "config_builder.h"
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
#include "test_paths.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using namespace plugslam;

namespace {

const char* kRun = R"(plugins: [sim, io, odometry]
source: {type: sim.Simulator2D, session: stage-0, lasers: [front_laser], odometry_noise: NOISE}
pipeline:
  tracker:
    type: sdk.MultiTracker2D
    motion: {type: odometry.WheelOdometry}
    aligner:
      min_inliers: 1
      slices:
        - {type: odometry.PriorSlice}
    splitter: {type: sdk.DistanceSplitter, distance: 1.0, angle: 0.5}
outputs:
  - {type: io.TrajectoryWriter, file: traj.tum, format: tum}
)";

std::string runText(const std::string& noise) {
  std::string text = kRun;
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
  runtime::PluginManager plugins;
  auto run = runtime::buildRun(runtime::loadConfigText(runText("0.0"), "run.yaml"), plugins);
  runtime::RunOptions options;
  options.out_dir = out.string();
  const auto report = runtime::runPipeline(*run, options);
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

}  // namespace
