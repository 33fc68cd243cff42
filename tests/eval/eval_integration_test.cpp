// ATE/RPE on the evo sample trajectories and crispness of the GMapping-corrected laser logs.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>

#include "carmen_scans.h"
#include "plugslam/eval/ate.h"
#include "plugslam/eval/crispness.h"
#include "plugslam/eval/relations.h"
#include "plugslam/eval/report.h"
#include "plugslam/eval/rpe.h"
#include "test_paths.h"

namespace plugslam {
namespace {

namespace fs = std::filesystem;

// The data folder ($PLUGSLAM_DATA or the default); it may not exist.
fs::path dataDir() { return plugslam::testing::dataDir(); }

// A file under the data folder, or nothing when the datasets are not installed.
std::optional<fs::path> dataFile(const std::string& rel) {
  const fs::path p = dataDir() / rel;
  if (dataDir().empty() || !fs::exists(p)) return std::nullopt;
  return p;
}

TEST(EvalIntegrationTest, TumFr1XyzRgbdslam) {
  const std::string gt_rel = "rgbd/tum-fr1_xyz-trajectories-evo/freiburg1_xyz-groundtruth.txt";
  const std::optional<fs::path> gt_file = dataFile(gt_rel);
  if (!gt_file) GTEST_SKIP() << "needs " << gt_rel << " under PLUGSLAM_DATA (not available)";
  const fs::path gt = *gt_file;
  const fs::path dir = gt.parent_path();
  const Trajectory ref = readTrajectory(gt.string());
  const Trajectory est = readTrajectory((dir / "freiburg1_xyz-rgbdslam.txt").string());
  EXPECT_EQ(est.size(), 788u);
  const AteResult ate = computeAte(ref, est, {Alignment::SE3, {0.01, 0.0}});
  std::cout << "fr1_xyz rgbdslam\n" << toMarkdown(ate) << toJson(ate) << "\n";
  // RGBDSLAM on fr1/xyz is published at about 1.4 cm ATE RMSE (Endres et al. 2014).
  EXPECT_GT(ate.translation.rmse, 0.005);
  EXPECT_LT(ate.translation.rmse, 0.03);
  EXPECT_GT(ate.translation.count, 700u);

  RpeOptions rpe;
  rpe.unit = RpeUnit::Seconds;
  rpe.delta = 1.0;
  const RpeResult r = computeRpe(ref, est, rpe);
  std::cout << toMarkdown(r);
  EXPECT_GT(r.translation.rmse, 0.005);
  EXPECT_LT(r.translation.rmse, 0.05);
}

TEST(EvalIntegrationTest, TumFr1XyzOrbMonoNeedsSim3) {
  const std::string gt_rel = "rgbd/tum-fr1_xyz-trajectories-evo/freiburg1_xyz-groundtruth.txt";
  const std::optional<fs::path> gt_file = dataFile(gt_rel);
  if (!gt_file) GTEST_SKIP() << "needs " << gt_rel << " under PLUGSLAM_DATA (not available)";
  const fs::path gt = *gt_file;
  const Trajectory ref = readTrajectory(gt.string());
  const Trajectory est =
      readTrajectory((gt.parent_path() / "freiburg1_xyz-ORB_kf_mono.txt").string());
  const AteResult se3 = computeAte(ref, est, {Alignment::SE3, {0.01, 0.0}});
  const AteResult sim3 = computeAte(ref, est, {Alignment::Sim3, {0.01, 0.0}});
  std::cout << "fr1_xyz ORB mono keyframes\n" << toMarkdown(se3) << toMarkdown(sim3);
  EXPECT_LT(sim3.translation.rmse, se3.translation.rmse);
  EXPECT_LT(sim3.translation.rmse, 0.05);
  EXPECT_NE(sim3.transform.scale, 1.0);
}

TEST(EvalIntegrationTest, Kitti00OrbAndSptam) {
  const std::string gt_rel = "stereo/kitti00-trajectories-evo/KITTI_00_gt.txt";
  const std::optional<fs::path> gt_file = dataFile(gt_rel);
  if (!gt_file) GTEST_SKIP() << "needs " << gt_rel << " under PLUGSLAM_DATA (not available)";
  const fs::path gt = *gt_file;
  const fs::path dir = gt.parent_path();
  const Trajectory ref = readKittiTrajectory(gt.string());
  EXPECT_EQ(ref.size(), 4541u);
  const Trajectory timed =
      readKittiTrajectory(gt.string(), (dir / "KITTI_00_gt_times.txt").string());
  EXPECT_NEAR(timed.endTime() - timed.startTime(), 470.0, 5.0);
  for (const char* name : {"KITTI_00_ORB.txt", "KITTI_00_SPTAM.txt"}) {
    const Trajectory est = readTrajectory((dir / name).string());
    const AteResult ate = computeAte(ref, est, {Alignment::SE3, {0.01, 0.0}});
    const AteResult raw = computeAte(ref, est, {Alignment::None, {0.01, 0.0}});
    RpeOptions o;
    o.unit = RpeUnit::Meters;
    o.delta = 100.0;
    const RpeResult rpe = computeRpe(ref, est, o);
    std::cout << name << "\n" << toMarkdown(ate) << toMarkdown(raw) << toMarkdown(rpe);
    EXPECT_EQ(ate.translation.count, 4541u);
    // Stereo SLAM on KITTI 00 is published at a few metres ATE (ORB-SLAM2: 1.3 m).
    EXPECT_GT(ate.translation.rmse, 0.5) << name;
    EXPECT_LT(ate.translation.rmse, 10.0) << name;
    EXPECT_LE(ate.translation.rmse, raw.translation.rmse + 1e-9) << name;
  }
}

struct LogCase {
  const char* file;
  double reference_crispness;  // the table, measured by an independent script
};

TEST(EvalIntegrationTest, CrispnessOfTheGmappingReferences) {
  const LogCase cases[] = {
      {"laser2d/intel-gfs-corrected/intel-corrected.log.gz", 0.0174},
      {"laser2d/freiburg-079-gfs-corrected/freiburg-079-corrected.log.gz", 0.0059},
      {"laser2d/freiburg-101-gfs-corrected/freiburg-101-corrected.log.gz", 0.0200},
      {"laser2d/freiburg-campus-gfs-corrected/freiburg-campus-corrected.log.gz", 0.0405},
      {"laser2d/seattle-gfs-corrected/seattle-corrected.log.gz", 0.0117},
      {"laser2d/edmonton-gfs-corrected/edmonton-corrected.log.gz", 0.0724},
  };
  int found = 0;
  for (const LogCase& c : cases) {
    const fs::path log = dataDir() / c.file;
    if (dataDir().empty() || !fs::exists(log)) continue;
    ++found;
    const test::CarmenScans data = test::readCarmenScans(log.string());
    const auto t0 = std::chrono::steady_clock::now();
    const CrispnessResult r = computeCrispness(data.scans);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cout << c.file << ": crispness " << r.mean << " m (table " << c.reference_crispness
              << "), " << r.matched_points << "/" << r.points << " points matched, " << r.scans
              << " scans, " << seconds << " s\n";
    EXPECT_GT(r.matched_points, r.points / 4) << c.file;
    // The table's script differs in details we cannot see (our figures run 15-35 % higher with
    // 1 deg / 0.5 deg beams from -90 deg, which of the layouts we tried gives the crispest maps).
    // Same order of magnitude is what can be asserted; comparisons use this implementation.
    EXPECT_GT(r.mean, 0.8 * c.reference_crispness) << c.file;
    EXPECT_LT(r.mean, 1.5 * c.reference_crispness) << c.file;

    // Independent ~3 cm / 0.3 deg noise on every pose blurs the map, though only a little where
    // many scans overlap (the nearest of many noisy copies stays close).
    std::vector<PosedScan> noisy = data.scans;
    for (std::size_t k = 0; k < noisy.size(); ++k) {
      const double s = std::sin(1.7 * double(k)), u = std::cos(2.3 * double(k));
      noisy[k].pose = Eigen::Translation2d(0.03 * s, 0.03 * u) * Eigen::Rotation2Dd(0.005 * s * u) *
                      noisy[k].pose;
    }
    const double noisy_mean = computeCrispness(noisy).mean;
    // A 5 cm jump halfway (a double wall) shows clearly.
    std::vector<PosedScan> doubled = data.scans;
    for (std::size_t k = doubled.size() / 2; k < doubled.size(); ++k) {
      doubled[k].pose = Eigen::Translation2d(0.05, 0.0) * doubled[k].pose;
    }
    const double doubled_mean = computeCrispness(doubled).mean;
    std::cout << "  with pose noise " << noisy_mean << " m, with a 5 cm jump " << doubled_mean
              << " m\n";
    EXPECT_GT(noisy_mean, r.mean) << c.file;
    EXPECT_GT(doubled_mean, r.mean) << c.file;
  }
  if (found == 0) GTEST_SKIP() << "no laser2d logs under PLUGSLAM_DATA";
}

TEST(EvalIntegrationTest, IntelReferenceAgainstItsOwnRelations) {
  const std::string log_rel = "laser2d/intel-gfs-corrected/intel-corrected.log.gz";
  const std::optional<fs::path> log_file = dataFile(log_rel);
  if (!log_file) GTEST_SKIP() << "needs " << log_rel << " under PLUGSLAM_DATA (not available)";
  const fs::path log = *log_file;
  const test::CarmenScans data = test::readCarmenScans(log.string());
  const std::vector<Relation> rel = relationsFromTrajectory(data.poses, 1.0);
  EXPECT_GT(rel.size(), data.poses.size());
  const RelationResult self = evaluateRelations(data.poses, rel, {0.01});
  EXPECT_LT(self.translation.mean, 1e-9);
  // 2 cm and 0.5 deg of noise on every pose: relation errors of that order.
  Trajectory noisy;
  for (const StampedPose& p : data.poses) {
    const double k = p.t;
    Eigen::Isometry3d q = p.pose;
    q.translation() += Eigen::Vector3d(0.02 * std::sin(7.1 * k), 0.02 * std::cos(3.3 * k), 0.0);
    q.linear() = q.linear() *
                 Eigen::AngleAxisd(0.5 * M_PI / 180 * std::sin(5.7 * k), Eigen::Vector3d::UnitZ())
                     .toRotationMatrix();
    noisy.push_back(p.t, q);
  }
  const RelationResult r = evaluateRelations(noisy, rel, {0.01});
  std::cout << "intel, reference + noise, " << rel.size() << " relations\n" << toMarkdown(r);
  EXPECT_GT(r.translation.mean, 0.005);
  EXPECT_LT(r.translation.mean, 0.1);
  EXPECT_GT(r.rotation_deg.mean, 0.1);
  EXPECT_LT(r.rotation_deg.mean, 1.5);
}

}  // namespace
}  // namespace plugslam
