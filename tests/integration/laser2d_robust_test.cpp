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

// Measured on the shipped config (scripts/bench/laser2d_robust.sh, one run each, issue 41's
// front-end: predict a covariance, search its window, refine, check): relations 0.042-0.045 m
// and 0.56-0.57 deg, crispness 0.0214-0.0218 against the reference's 0.0229, no failure.
// Odometry scaled -10 % and every 5th ODOM line failed with the correction gate before (0.115 m;
// 2.43 m / 10.8 deg).
INSTANTIATE_TEST_SUITE_P(Issue20, DegradedIntel,
                         ::testing::Values("scale_up", "scale_down", "drift", "sparse"),
                         variantName);
// Open (issue 41), disabled until the front-end meets them (same bounds). Laser only: 0.36 m /
// 0.90 deg (5.65 m / 41 deg before the search weighed constant velocity's learned typical
// error): steps of a metre along corridors whose look-alikes a metre back fit the one- or
// two-scan local maps better than the true pose by more than the prior's margin. Decimated x3
// 1.05 m / 9 deg (10 frames with too few pairs on 3 m steps), x5 10.5 m (53 such frames).
// Run them with --gtest_also_run_disabled_tests.
INSTANTIATE_TEST_SUITE_P(DISABLED_Issue41Open, DegradedIntel,
                         ::testing::Values("no_odom", "decimate3", "decimate5"), variantName);

// Degraded variants of the other shared logs that the shipped config keeps a map like the
// reference's (the issue's full target), each measured by scripts/bench/laser2d_robust.sh (one
// run each): laser only on freiburg-101 (0.032 m / 0.27 deg) and on seattle (0.030 m / 0.27 deg,
// crispness 0.0121 against the reference's 0.0143; 17.8 m / 38 deg before the search weighed
// constant velocity's learned typical error: a look-alike turned 1.7 rad from the truth scored
// best in the window of a 5 s gap), every 5th ODOM line on seattle and
// freiburg-101 (0.026 m and 0.032 m), freiburg-101 decimated x3 and x5 (0.039 m, 0.043 m).
struct Case {
  std::string log, file, variant;
};

// gtest lists a parameter by this (else by its bytes, which differ from run to run).
void PrintTo(const Case& c, std::ostream* os) { *os << c.log << " " << c.variant; }

class OtherLogs : public ::testing::TestWithParam<Case> {};

TEST_P(OtherLogs, StaysAMapLikeTheReference) {
  expectAMapLikeTheReference(GetParam().log, GetParam().file, GetParam().variant);
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  std::string name =
      info.param.log.substr(0, info.param.log.find("-gfs")) + "_" + info.param.variant;
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

INSTANTIATE_TEST_SUITE_P(
    Issue20, OtherLogs,
    ::testing::Values(
        Case{"freiburg-101-gfs-corrected", "freiburg-101-corrected.log.gz", "no_odom"},
        Case{"seattle-gfs-corrected", "seattle-corrected.log.gz", "no_odom"},
        Case{"seattle-gfs-corrected", "seattle-corrected.log.gz", "sparse"},
        Case{"freiburg-101-gfs-corrected", "freiburg-101-corrected.log.gz", "sparse"},
        Case{"freiburg-101-gfs-corrected", "freiburg-101-corrected.log.gz", "decimate3"},
        Case{"freiburg-101-gfs-corrected", "freiburg-101-corrected.log.gz", "decimate5"}),
    caseName);
// Open (issue 41): seattle decimated x3, 0.77 m / 9.1 deg (a turn the odometry's covariance did
// not cover).
INSTANTIATE_TEST_SUITE_P(
    DISABLED_Issue41Open, OtherLogs,
    ::testing::Values(Case{"seattle-gfs-corrected", "seattle-corrected.log.gz", "decimate3"}),
    caseName);

// Odometry arriving less often than the scans, where it matters most: freiburg-079 scans every
// 0.25 s, so with every 5th ODOM line (about 1.1 s apart) most frames get the previous frame's
// reading again. A correction gate on the prediction threw the right alignments away (24 gated
// frames, 5.24 m / 35 deg). odometry.WheelOdometry predicts no motion for such a frame, with the
// covariance of what the robot may have done since the reading (its recent speed), and the
// search covers it: no failure, 0.041 m / 0.72 deg, crispness 0.0074 against the reference's
// 0.0079 (scripts/bench/laser2d_robust.sh).
TEST(DegradedFreiburg079, EveryFifthOdometryLineStaysAMapLikeTheReference) {
  expectAMapLikeTheReference("freiburg-079-gfs-corrected", "freiburg-079-corrected.log.gz",
                             "sparse");
}

}  // namespace
