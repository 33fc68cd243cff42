// Issue 20: the shipped 2D laser config, unchanged, on degraded variants of one shared log
// (intel): one case per kind of degradation. The variants are written from the original into
// this test's temporary folder by scripts/bench/laser2d_variants.py (the bench's own generator),
// never stored. Each case must stay a map like the reference's: relations against GMapping's
// poses <= 0.15 m and <= 1 deg (the issue's broken-map bound), at least as crisp, with >= 0.9x its
// coverage, and the run says why frames failed.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "plugslam/eval/relations.h"
#include "plugslam/trajectory.h"
#include "temp_dir.h"
#include "run_command.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using namespace plugslam;

namespace {

using Result = plugslam::testing::CommandResult;

Result shell(const std::string& cmd) {
  return plugslam::testing::runCommand(cmd);
}

Result plugslamCli(const std::string& args) {
  return shell("cd " + plugslam::testing::sourceDir() + " && " + plugslam::testing::buildDir() +
               "/bin/plugslam " + args);
}

nlohmann::json readJson(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return nlohmann::json::parse(ss.str(), nullptr, false);
}

// Runs the shipped config on `variant` of the shared log `name` (laser2d/<name>/<file>) and checks
// it stays a map like the reference's.
void expectAMapLikeTheReference(const std::string& name, const std::string& file,
                                const std::string& variant) {
  const std::string log = plugslam::testing::dataDir() + "/laser2d/" + name + "/" + file;
  if (!fs::exists(log))
    GTEST_SKIP() << name << " log not found at " << log << " (set PLUGSLAM_DATA)";
  if (shell("python3 --version").code != 0)
    GTEST_SKIP() << "python3 not found (writes the variant)";
  const plugslam::testing::TempDir tmp("plugslam_robust");
  const fs::path vlog = tmp.path() / (variant + ".log.gz");
  Result r = shell("python3 " + plugslam::testing::sourceDir() +
                   "/scripts/bench/laser2d_variants.py " + log + " " + tmp.path().string() + " " +
                   variant);
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(vlog));
  const fs::path out = tmp.path() / "run";
  // The shipped threaded back-end, as users run it (the targets hold in every run).
  r = plugslamCli("run configs/laser2d_carmen.yaml -o " + out.string() +
                  " --set source.path=" + vlog.string());
  ASSERT_EQ(r.code, 0) << r.out;
  if (variant == "no_odom") {  // the same config runs laser only, and says so once
    EXPECT_NE(r.out.find("tracking without odometry"), std::string::npos) << r.out;
  }

  const nlohmann::json run = readJson(out / "run.json");
  ASSERT_TRUE(run.is_object());
  uint64_t reasons = 0;
  for (const auto& [k, v] : run["tracking_failure_reasons"].items()) reasons += v.get<uint64_t>();
  EXPECT_EQ(reasons, run["tracking_failures"].get<uint64_t>()) << "every failure has a reason";

  const Trajectory est = readTrajectory((out / "trajectory.tum").string());
  const Trajectory ref = readTrajectory((out / "reference.tum").string());
  const RelationResult rel = evaluateRelations(est, relationsFromTrajectory(ref, 2.0));
  // Issue 20's bound for a map that did not break (the reference's own noise is 3-7 cm).
  EXPECT_LE(rel.translation.mean, 0.15) << variant;
  EXPECT_LE(rel.rotation_deg.mean, 1.0) << variant;

  nlohmann::json crisp[2];
  const char* files[2] = {"trajectory.tum", "reference.tum"};
  for (int i = 0; i < 2; ++i) {
    const fs::path json = tmp.path() / (std::string("crisp_") + std::to_string(i) + ".json");
    r = plugslamCli("eval crispness " + vlog.string() + " " + (out / files[i]).string() +
                    " --format json -o " + json.string());
    ASSERT_EQ(r.code, 0) << r.out;
    crisp[i] = readJson(json);
  }
  std::printf("%s %s: %s failures, relations %.4f m %.3f deg, crispness %.4f / %.4f, coverage "
              "%.3f / %.3f\n",
              name.c_str(), variant.c_str(), run["tracking_failures"].dump().c_str(),
              rel.translation.mean,
              rel.rotation_deg.mean, crisp[0]["mean_m"].get<double>(),
              crisp[1]["mean_m"].get<double>(), crisp[0]["coverage"].get<double>(),
              crisp[1]["coverage"].get<double>());
  // Issue 20: at least as crisp as GMapping's map, with at least 0.9x its coverage.
  EXPECT_LE(crisp[0]["mean_m"].get<double>(), crisp[1]["mean_m"].get<double>()) << variant;
  EXPECT_GE(crisp[0]["coverage"].get<double>(), 0.9 * crisp[1]["coverage"].get<double>())
      << variant;
}

class DegradedIntel : public ::testing::TestWithParam<std::string> {};

TEST_P(DegradedIntel, StaysAMapLikeTheReference) {
  expectAMapLikeTheReference("intel-gfs-corrected", "intel-corrected.log.gz", GetParam());
}

std::string variantName(const ::testing::TestParamInfo<std::string>& info) { return info.param; }

// Measured on the shipped config (scripts/bench/laser2d_robust.sh, one threaded run each):
// relations 0.043 m and 0.57 deg, crispness 0.0216-0.0217 against the reference's 0.0229,
// coverage 0.944 against 0.945, no failure.
INSTANTIATE_TEST_SUITE_P(Issue20, DegradedIntel, ::testing::Values("scale_up", "drift"),
                         variantName);
// Issue 20's open targets, disabled until the shipped front-end meets them (same bounds; measured
// on the shipped config): odometry scaled -10 % 0.115 m, crispness 0.0246 against 0.0229,
// coverage 0.917 against 0.945; odometry every 5th line 2.43 m / 10.8 deg (0.069 m, crispness
// 0.0267 before new readings older than their frame said their unseen part: the front-end is
// better, 25 -> 15 steps off, but frame 219's turn, gated 0.58 rad off, no longer cancels against
// the next frame's, and its fallback edge (0.05 rad) holds the error); laser only 0.193 m /
// 0.60 deg, crispness 0.0268 against 0.0229 (13.9 m / 68 deg before the seeder's search checked
// every frame without odometry); decimated x3, with the gate grown with the predicted step
// (max_correction_per_motion), 0.075 m but 1.20 deg, crispness 0.0405 against 0.0369 in a
// threaded run (1.13 m in a deterministic one: 4 failures), and x5 11.3 m / 62 deg (31 frames
// with too few inliers on 5 m steps).
// With laser2d.CorrelativeSeeder searching frames with odometry too (with_measured_motion),
// every-5th passes (0.044 m), and with odometry.PriorSlice's disagreement_frames 10 also scale
// -10 %, but freiburg-campus breaks (seeder: 0.074 -> 9.05 m, slides the search confirms), so
// the shipped config searches only the frames without odometry.
// Run them with --gtest_also_run_disabled_tests.
INSTANTIATE_TEST_SUITE_P(DISABLED_Issue20Open, DegradedIntel,
                         ::testing::Values("scale_down", "sparse", "no_odom", "decimate3",
                                           "decimate5"),
                         variantName);

// Degraded variants of the other shared logs that the shipped config keeps a map like the
// reference's (the issue's full target), each measured by scripts/bench/laser2d_robust.sh in one
// threaded run:
// - laser only (no ODOM lines), scans about 0.9-1 m and up to 30-80 deg apart. Before the
//   seeder's search checked every frame without measured motion both maps broke (seattle
//   12.6 m / 74 deg, freiburg-101 24.9 m / 57 deg); since: 0.032 m / 0.26 deg, 0.033 m / 0.28 deg.
// - every 5th ODOM line: a new reading older than its frame now says the part of the step after
//   it (the gate and prior widen by it, the seeder checks the frame). Before: seattle 0.66 m /
//   6.3 deg (one turn gated), freiburg-101 0.130 m / 2.99 deg (9 gated frames); since:
//   0.032 m / 0.27 deg, 0.036 m / 0.27 deg.
// - seattle decimated x3 (every reading kept, each older than its scan): 1.47 m / 15.6 deg
//   before, 0.029 m / 0.31 deg since.
struct Case {
  std::string log, file, variant;
};

// gtest lists a parameter by this (else by its bytes, which differ from run to run).
void PrintTo(const Case& c, std::ostream* os) { *os << c.log << " " << c.variant; }

class OtherLogs : public ::testing::TestWithParam<Case> {};

TEST_P(OtherLogs, StaysAMapLikeTheReference) {
  expectAMapLikeTheReference(GetParam().log, GetParam().file, GetParam().variant);
}

INSTANTIATE_TEST_SUITE_P(
    Issue20, OtherLogs,
    ::testing::Values(
        Case{"seattle-gfs-corrected", "seattle-corrected.log.gz", "no_odom"},
        Case{"freiburg-101-gfs-corrected", "freiburg-101-corrected.log.gz", "no_odom"},
        Case{"seattle-gfs-corrected", "seattle-corrected.log.gz", "sparse"},
        Case{"freiburg-101-gfs-corrected", "freiburg-101-corrected.log.gz", "sparse"},
        Case{"seattle-gfs-corrected", "seattle-corrected.log.gz", "decimate3"}),
    [](const ::testing::TestParamInfo<Case>& info) {
      std::string name = info.param.log.substr(0, info.param.log.find("-gfs")) + "_" +
                         info.param.variant;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// Odometry arriving less often than the scans, where it matters most: freiburg-079 scans every
// 0.25 s, so with every 5th ODOM line (about 1.1 s apart) most frames get the previous frame's
// reading again. Taken as the pose at the frame it predicted no motion, the correction gate threw
// the right alignments away and the map broke (24 gated frames, relations 5.24 m / 35 deg).
// odometry.WheelOdometry carries such a reading on with the recent velocity and the gate and the
// prior widen by what it extrapolated: 3 gated frames, 0.049 m / 1.06 deg, crispness 0.0091
// against the reference's 0.0079. The extrapolated part is a constant-velocity guess, so the
// seeder's search checks those frames as it does laser-only ones: no failure, 0.042 m /
// 0.72 deg, crispness 0.0074 (one threaded run of scripts/bench/laser2d_robust.sh).
TEST(DegradedFreiburg079, EveryFifthOdometryLineStaysAMapLikeTheReference) {
  expectAMapLikeTheReference("freiburg-079-gfs-corrected", "freiburg-079-corrected.log.gz",
                             "sparse");
}

}  // namespace
