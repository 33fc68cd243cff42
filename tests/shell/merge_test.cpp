// `plugslam merge` in-process: two sessions of the simulated office started at different, unknown
// places join in one frame (their trajectories against ground truth with one alignment); a
// session of another building is reported and left out; sessions of other cues are refused.
#include "session/merge.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "plugslam/eval/ate.h"
#include "run_config.h"
#include "runner.h"
#include "session/session.h"
#include "sim_worlds.h"
#include "temp_dir_test.h"
#include "test_paths.h"

using namespace plugslam;
using namespace plugslam::runtime;
namespace fs = std::filesystem;

namespace {

// `t` moved by the similarity `s` (the alignment one trajectory found).
Trajectory moved(const Trajectory& t, const SimilarityTransform& s) {
  std::vector<StampedPose> out;
  for (StampedPose p : t) {
    p.pose.linear() = s.rotation * p.pose.linear();
    p.pose.translation() = s.scale * s.rotation * p.pose.translation() + s.translation;
    out.push_back(p);
  }
  return Trajectory(std::move(out));
}

class Merge : public plugslam::testing::TempDirTest {
 protected:
  Merge() : TempDirTest("plugslam_merge") {}
  // Why the test cannot run: a plugin it needs is not built (empty: it can).
  std::string pluginsMissing(const std::vector<std::string>& cues = {"laser2d", "odometry"}) {
    const std::string plugin_dir = plugslam::testing::buildDir() + "/plugins";
    std::vector<std::string> needed = {"sim", "io"};
    needed.insert(needed.end(), cues.begin(), cues.end());
    for (const std::string& p : needed)
      if (!fs::exists(plugin_dir + "/plugslam_" + p + ".so"))
        return "plugin '" + std::string(p) + "' is not built in " + plugin_dir;
    plugins_.addSearchDir(plugin_dir);
    plugins_.addSearchDir(plugslam::testing::buildDir() + "/tests/plugins");
    return "";
  }
  // A shipped config (the simulated office's unless told) with `sets`, mapped and saved as
  // session `name`; its ground truth.
  Trajectory mapAndSave(const std::string& name, const std::vector<std::string>& sets,
                        const std::string& config = "sim2d_single_laser.yaml") {
    ConfigDocument doc = loadConfigFile(plugslam::testing::sourceDir() + "/configs/" + config);
    applyOverride(doc, "outputs=[]");
    applyOverride(doc, "pipeline.graph.deterministic=true");
    for (const auto& s : sets) applyOverride(doc, s);
    auto run = buildRun(doc, plugins_);
    RunOptions o;
    o.out_dir = (dir_ / ("run_" + name)).string();
    runPipeline(*run, o);
    saveSession((dir_ / name).string(), resolvedYaml(doc), *run->pipeline);
    return run->pipeline->result().reference;
  }
  MergeReport merge(const std::vector<std::string>& names) {
    MergeOptions o;
    for (const auto& n : names) o.sessions.push_back((dir_ / n).string());
    o.out_dir = (dir_ / "merged").string();
    return mergeSessions(o, plugins_);
  }
  // `plugslam run CONFIG --session SESSION --localize --start-anywhere` with `sets` (and no
  // outputs, a deterministic graph); the run stays in localized_ for its result.
  RunReport localizeFromAnywhere(const std::string& session, const std::vector<std::string>& sets,
                                 const std::string& config = "sim2d_single_laser.yaml") {
    ConfigDocument doc = loadConfigFile(plugslam::testing::sourceDir() + "/configs/" + config);
    for (const char* s : {"outputs=[]", "pipeline.graph.deterministic=true",
                          "pipeline.graph.join_by_estimate=false"})
      applyOverride(doc, s);
    for (const auto& s : sets) applyOverride(doc, s);
    localized_ = buildRun(doc, plugins_);
    const SessionMaps saved = loadSessionMaps(readSessionManifest((dir_ / session).string()));
    localized_->pipeline->restoreSession(saved.maps, saved.edges, true, false);
    RunOptions o;
    o.out_dir = (dir_ / "run_localize").string();
    return runPipeline(*localized_, o);
  }
  // The ATE of the localized run's poses from frame `first` on against its truth, in the frame
  // of `session`, whose own trajectory `alignment` puts on `session_truth`.
  AteResult localizedAte(int64_t first, const std::string& session,
                         const Trajectory& session_truth, Alignment alignment) const {
    AteOptions align;
    align.alignment = alignment;
    const AteResult frame = computeAte(
        session_truth, readTumTrajectory((dir_ / session / "trajectory.tum").string()), align);
    const RunResult result = localized_->pipeline->result();
    std::vector<StampedPose> after;
    for (size_t i = static_cast<size_t>(first); i < result.trajectory.size(); ++i)
      after.push_back(result.trajectory[i]);
    AteOptions none;
    none.alignment = Alignment::None;
    return computeAte(result.reference, moved(Trajectory(std::move(after)), frame.transform),
                      none);
  }
  Trajectory merged(int k) const {
    return readTumTrajectory((dir_ / "merged" / ("trajectory_" + std::to_string(k) + ".tum")).string());
  }
  PluginManager plugins_;
  std::shared_ptr<RunConfig> localized_;
};

TEST_F(Merge, TwoOfficeSessionsStartedApartJoinInOneFrame) {
  if (const std::string why = pluginsMissing(); !why.empty()) GTEST_SKIP() << why;
  // Two tours starting 4.75 m apart: each run's estimate is in its own start frame.
  const Trajectory truth0 = mapAndSave("s0", {"source.session=stage-0"});
  const Trajectory truth1 = mapAndSave("s1", {"source.session=stage-1", "source.seed=1"});
  const MergeReport r = merge({"s0", "s1"});
  ASSERT_EQ(r.inputs.size(), 2u);
  EXPECT_TRUE(r.inputs[0].joined && r.inputs[1].joined);
  EXPECT_GE(r.links, 1u);
  EXPECT_TRUE(fs::exists(dir_ / "merged" / "session" / "session.yaml"));
  EXPECT_TRUE(fs::exists(dir_ / "merged" / "merge.json"));
  // One alignment, found on the first trajectory, must put the second on its truth too.
  AteOptions se2;
  se2.alignment = Alignment::SE2;
  const AteResult first = computeAte(truth0, merged(1), se2);
  AteOptions none;
  none.alignment = Alignment::None;
  const AteResult second = computeAte(truth1, moved(merged(2), first.transform), none);
  std::cout << "merged office: ATE " << first.translation.rmse << " m and "
            << second.translation.rmse << " m in one frame, " << r.links << " links\n";
  EXPECT_LT(first.translation.rmse, 0.05);
  EXPECT_LT(second.translation.rmse, 0.05);
  // Unmerged, the second run's own frame is its start's: metres off in that frame.
  const Trajectory own = readTumTrajectory((dir_ / "s1" / "trajectory.tum").string());
  EXPECT_GT(computeAte(truth1, moved(own, first.transform), none).translation.rmse, 1.0);
}

// The landmark cue: two RGB-D sessions of the rendered room, the second from the loop's 10th
// second on, seen from 5 cm aside and turned 0.03 rad, each in its own start frame, join by
// appearance place recognition (sdk.AppearanceDetector, configs/parts/appearance_loops.yaml);
// the second tour localizes in the first session from its unknown start.
TEST_F(Merge, RgbdSessionsJoinAndLocalizeByAppearance) {
  if (const std::string why = pluginsMissing({"rgbd"}); !why.empty()) GTEST_SKIP() << why;
  const std::string config = "sim3d_rgbd_slam.yaml";
  const Trajectory truth0 = mapAndSave("r0", {}, config);
  ASSERT_GT(truth0.size(), 600u);
  Eigen::Isometry3d aside = Eigen::Isometry3d::Identity();
  aside.translate(Eigen::Vector3d(0.05, 0, 0));
  aside.rotate(Eigen::AngleAxisd(0.03, Eigen::Vector3d::UnitY()));  // the camera's vertical axis
  std::vector<StampedPose> second;
  for (size_t i = 300; i < truth0.size(); ++i)
    second.push_back({truth0[i].t, truth0[i].pose * aside});
  const std::string path = (dir_ / "second.tum").string();
  writeTumTrajectory(Trajectory(std::move(second)), path);
  const Trajectory truth1 =
      mapAndSave("r1", {"source.trajectory=" + path, "source.anchor=false"}, config);
  const MergeReport r = merge({"r0", "r1"});
  ASSERT_EQ(r.inputs.size(), 2u);
  ASSERT_TRUE(r.inputs[1].joined) << "the second session was not joined";
  AteOptions se3;
  se3.alignment = Alignment::SE3;
  const AteResult first = computeAte(truth0, merged(1), se3);
  AteOptions none;
  none.alignment = Alignment::None;
  const AteResult other = computeAte(truth1, moved(merged(2), first.transform), none);
  std::cout << "merged room: ATE " << first.translation.rmse << " m and "
            << other.translation.rmse << " m in one frame, " << r.links << " links\n";
  EXPECT_LT(first.translation.rmse, 0.05);
  EXPECT_LT(other.translation.rmse, 0.05);

  // The second tour localized in the first session from its unknown start (`--localize
  // --start-anywhere`): it locks on within a second and then follows the truth in that frame.
  const RunReport report = localizeFromAnywhere(
      "r0", {"source.trajectory=" + path, "source.anchor=false"}, config);
  ASSERT_GE(report.locked_on_after, 0) << "never locked on";
  EXPECT_LE(report.locked_on_after, 30);  // 1 s of the camera
  const AteResult localized = localizedAte(report.locked_on_after, "r0", truth0, Alignment::SE3);
  std::cout << "localized from anywhere: locked on after " << report.locked_on_after
            << " frames, then ATE " << localized.translation.rmse << " m\n";
  EXPECT_LT(localized.translation.rmse, 0.05);
}

TEST_F(Merge, ASessionOfAnotherBuildingIsReportedNotMerged) {
  if (const std::string why = pluginsMissing(); !why.empty()) GTEST_SKIP() << why;
  // Another building: nothing like the office's rooms and corridors.
  const fs::path world = dir_ / "hall.txt";
  plugslam::testing::writeSevenSidedHall(world.string());
  mapAndSave("s0", {"source.session=stage-0"});
  mapAndSave("s1", {"source.session=stage-1", "source.seed=1"});
  mapAndSave("hall", {"source.session=stage-0", "source.world=" + world.string(),
                      "source.start=[0, 0]"});
  const MergeReport r = merge({"s0", "hall", "s1"});
  ASSERT_EQ(r.inputs.size(), 3u);
  EXPECT_TRUE(r.inputs[0].joined);
  EXPECT_FALSE(r.inputs[1].joined) << "the hall was welded to the office";
  EXPECT_TRUE(r.inputs[2].joined);
  EXPECT_EQ(r.maps, r.inputs[0].maps + r.inputs[2].maps);  // the hall is left out
  const auto json = nlohmann::json::parse(std::ifstream(dir_ / "merged" / "merge.json"));
  EXPECT_FALSE(json["sessions"][1]["joined"].get<bool>());
  // Alone with the office, nothing merges: nothing is written.
  fs::remove_all(dir_ / "merged");
  const MergeReport apart = merge({"s0", "hall"});
  EXPECT_FALSE(apart.inputs[1].joined);
  EXPECT_FALSE(fs::exists(dir_ / "merged" / "session"));
}

TEST_F(Merge, ARunStartedElsewhereJoinsTheSessionByPlaceRecognition) {
  if (const std::string why = pluginsMissing(); !why.empty()) GTEST_SKIP() << why;
  const Trajectory truth0 = mapAndSave("s0", {"source.session=stage-0"});
  // `plugslam run CONFIG --session s0 --start-anywhere`: a tour starting 4.75 m away.
  ConfigDocument doc =
      loadConfigFile(plugslam::testing::sourceDir() + "/configs/sim2d_single_laser.yaml");
  for (const char* s : {"outputs=[]", "pipeline.graph.deterministic=true",
                        "source.session=stage-1", "source.seed=1",
                        "pipeline.graph.join_by_estimate=false"})
    applyOverride(doc, s);
  auto run = buildRun(doc, plugins_);
  const SessionMaps saved = loadSessionMaps(readSessionManifest((dir_ / "s0").string()));
  run->pipeline->restoreSession(saved.maps, saved.edges, false);
  RunOptions o;
  o.out_dir = (dir_ / "run_s1").string();
  const RunReport report = runPipeline(*run, o);
  ASSERT_EQ(report.graph_components.size(), 1u) << "the run was not joined to the session";
  // The run's poses are in the session's frame: the session's alignment to its truth fits them.
  AteOptions se2;
  se2.alignment = Alignment::SE2;
  const AteResult session = computeAte(
      truth0, readTumTrajectory((dir_ / "s0" / "trajectory.tum").string()), se2);
  AteOptions none;
  none.alignment = Alignment::None;
  const RunResult result = run->pipeline->result();
  const AteResult joined =
      computeAte(result.reference, moved(result.trajectory, session.transform), none);
  std::cout << "run joined to the session: ATE " << joined.translation.rmse
            << " m in the session's frame\n";
  EXPECT_LT(joined.translation.rmse, 0.05);
}

TEST_F(Merge, LocalizationFromAnUnknownStartLocksOnAndFollowsTheTruth) {
  if (const std::string why = pluginsMissing(); !why.empty()) GTEST_SKIP() << why;
  const Trajectory truth1 = mapAndSave("s1", {"source.session=stage-1", "source.seed=1"});
  // `plugslam run CONFIG --session s1 --localize --start-anywhere`: a tour starting 4.75 m from
  // the session's start.
  const RunReport report = localizeFromAnywhere("s1", {"source.session=stage-0"});
  ASSERT_GE(report.locked_on_after, 0) << "never locked on";
  std::cout << "locked on after " << report.locked_on_after << " of " << report.frames
            << " frames\n";
  // The place it sees is searched from the first frame on, not once a local map closed.
  EXPECT_LE(report.locked_on_after, 20);
  // Every pose from the lock-on on, in the session's frame, against the truth.
  const AteResult localized = localizedAte(report.locked_on_after, "s1", truth1, Alignment::SE2);
  std::cout << "after lock-on: ATE " << localized.translation.rmse << " m, max "
            << localized.translation.max << " m\n";
  EXPECT_LT(localized.translation.rmse, 0.05);
  EXPECT_LT(localized.translation.max, 0.2);
}

TEST_F(Merge, LocalizationInAnotherBuildingNeverLocksOn) {
  if (const std::string why = pluginsMissing(); !why.empty()) GTEST_SKIP() << why;
  const fs::path world = dir_ / "hall.txt";
  plugslam::testing::writeSevenSidedHall(world.string());
  mapAndSave("hall", {"source.session=stage-0", "source.world=" + world.string(),
                      "source.start=[0, 0]"});
  // A tour of the office localized in the hall's session: no place of it is there.
  const RunReport report = localizeFromAnywhere("hall", {"source.session=stage-0"});
  EXPECT_EQ(report.locked_on_after, -1) << "locked on in a building it is not in";
  EXPECT_GT(report.frames, 100);
}

TEST_F(Merge, SessionsOfOtherCuesAreRefused) {
  if (const std::string why = pluginsMissing(); !why.empty()) GTEST_SKIP() << why;
  mapAndSave("laser", {"source.session=stage-0", "max_frames=50"});
  // The landmark test plugin's pipeline: a 2D session too, but of landmarks.
  ConfigDocument doc =
      loadConfigFile(plugslam::testing::sourceDir() + "/tests/shell/lmsim.yaml");
  applyOverride(doc, "max_frames=50");
  auto run = buildRun(doc, plugins_);
  RunOptions o;
  o.out_dir = (dir_ / "run_lm").string();
  runPipeline(*run, o);
  saveSession((dir_ / "landmarks").string(), resolvedYaml(doc), *run->pipeline);
  try {
    merge({"laser", "landmarks"});
    FAIL() << "sessions of different cues merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("do not merge"), std::string::npos) << e.what();
  }
  EXPECT_THROW(merge({"laser"}), InputError);
}

}  // namespace
