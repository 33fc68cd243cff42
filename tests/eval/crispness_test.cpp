#include "plugslam/eval/crispness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "plugslam/errors.h"

namespace plugslam {
namespace {

Eigen::Isometry2d pose2(double x, double y, double yaw) {
  Eigen::Isometry2d p = Eigen::Isometry2d::Identity();
  p.linear() = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  p.translation() = Eigen::Vector2d(x, y);
  return p;
}

// The walls of a 6 x 6 m room sampled every 5 cm. Each scan sees every wall point, expressed in
// the frame of a robot driving a circle inside; estimate_error moves where scans are placed.
std::vector<PosedScan> squareRoom(int scans, const std::function<Eigen::Isometry2d(int)>& error) {
  std::vector<Eigen::Vector2d> world;
  for (int i = 0; i < 120; ++i) {
    const double s = -3.0 + 0.05 * i;
    world.emplace_back(s, -3.0);
    world.emplace_back(3.0, s);
    world.emplace_back(-s, 3.0);
    world.emplace_back(-3.0, -s);
  }
  std::vector<PosedScan> out;
  for (int k = 0; k < scans; ++k) {
    const double a = 2 * M_PI * k / scans;
    const Eigen::Isometry2d truth = pose2(1.5 * std::cos(a), 1.5 * std::sin(a), a + M_PI / 2);
    PosedScan s;
    for (const Eigen::Vector2d& w : world) s.points.push_back(truth.inverse() * w);
    s.pose = error(k) * truth;
    out.push_back(std::move(s));
  }
  return out;
}

TEST(CrispnessTest, PerfectPosesGiveZero) {
  const auto scans = squareRoom(100, [](int) { return Eigen::Isometry2d::Identity(); });
  const CrispnessResult r = computeCrispness(scans);
  EXPECT_EQ(r.points, 100u * 480u);
  EXPECT_EQ(r.matched_points, r.points);
  EXPECT_NEAR(r.mean, 0.0, 1e-12);
}

TEST(CrispnessTest, HalfTheScansShiftedGiveTheShift) {
  // Scans 50..99 placed 2 cm off along x. With a gap of 50, every scan's allowed partners are in
  // the other half, and the nearest wall point of the other half is exactly 2 cm away (the wall
  // points are 5 cm apart).
  const auto scans = squareRoom(
      100, [](int k) { return k >= 50 ? pose2(0.02, 0.0, 0.0) : Eigen::Isometry2d::Identity(); });
  const CrispnessResult r = computeCrispness(scans);
  EXPECT_EQ(r.matched_points, r.points);
  EXPECT_NEAR(r.mean, 0.02, 1e-9);
  // Nothing within 1 cm: no point has a neighbour, the mean is 0 by convention.
  CrispnessOptions tight;
  tight.radius = 0.01;
  const CrispnessResult none = computeCrispness(scans, tight);
  EXPECT_EQ(none.matched_points, 0u);
  EXPECT_EQ(none.mean, 0.0);
  // With a gap of 1, scans of the same half are allowed too, and they coincide.
  CrispnessOptions gap1;
  gap1.min_index_gap = 1;
  EXPECT_NEAR(computeCrispness(scans, gap1).mean, 0.0, 1e-12);
  // Within 10 scans every scan has a neighbour of its own half, which coincides with it.
  CrispnessOptions local;
  local.min_index_gap = 1;
  local.max_index_gap = 10;
  const CrispnessResult w = computeCrispness(scans, local);
  EXPECT_EQ(w.max_index_gap, 10);
  EXPECT_NEAR(w.mean, 0.0, 1e-12);  // the coinciding neighbour is always the nearest
  // A window that only reaches the other half measures the 2 cm shift again.
  local.min_index_gap = 50;
  local.max_index_gap = 60;
  EXPECT_NEAR(computeCrispness(scans, local).mean, 0.02, 1e-9);
}

TEST(CrispnessTest, GrowsWithThePoseError) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::Isometry2d> noise;
  for (int k = 0; k < 150; ++k) noise.push_back(pose2(n(rng), n(rng), 0.2 * n(rng)));
  double previous = 0.0;
  for (double sigma : {0.002, 0.01, 0.03}) {
    const auto scans = squareRoom(150, [&](int k) {
      const Eigen::Isometry2d& e = noise[static_cast<std::size_t>(k)];
      return pose2(sigma * e.translation().x(), sigma * e.translation().y(),
                   sigma * Eigen::Rotation2Dd(e.linear()).angle());
    });
    const double c = computeCrispness(scans).mean;
    EXPECT_GT(c, previous) << "sigma " << sigma;
    previous = c;
  }
}

TEST(CrispnessTest, ThreadCountDoesNotChangeTheResult) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0.0, 0.01);
  const auto scans = squareRoom(120, [&](int) { return pose2(n(rng), n(rng), 0.1 * n(rng)); });
  CrispnessOptions one, four;
  four.threads = 4;
  const CrispnessResult a = computeCrispness(scans, one);
  const CrispnessResult b = computeCrispness(scans, four);
  EXPECT_EQ(a.mean, b.mean);
  EXPECT_EQ(a.matched_points, b.matched_points);
}

TEST(CrispnessTest, CoverageOfAHandComputedCase) {
  // Three scans, gap 2: only scans 0 and 2 are partners; scan 1 (its points on top of scan 0's)
  // has none. Scan 2 is placed 2 m along x, so its points land at x = 0.1, 1.2 and 9.
  //   scan 0 (0, 0): nearest partner point 0.1 m away -> matched
  //   scan 0 (1, 0): 0.2 m -> matched;   scan 0 (5, 0): 4 m -> not
  //   scan 1: no partner scan -> 2 points not matched
  //   scan 2 (0.1, 0): 0.1 m, (1.2, 0): 0.2 m -> matched; (9, 0): 4 m -> not
  // coverage = 4 / 8 = 0.5, mean = (0.1 + 0.2 + 0.1 + 0.2) / 4 = 0.15. At radius 0.15 only the
  // two 0.1 m pairs remain: coverage 2 / 8, mean 0.1.
  std::vector<PosedScan> scans(3);
  scans[0].points = {{0, 0}, {1, 0}, {5, 0}};
  scans[1].points = {{0, 0.05}, {1, 0.05}};
  scans[2].points = {{-1.9, 0}, {-0.8, 0}, {7, 0}};
  scans[2].pose = pose2(2.0, 0.0, 0.0);
  CrispnessOptions o;
  o.min_index_gap = 2;
  CrispnessResult r = computeCrispness(scans, o);
  EXPECT_EQ(r.points, 8u);
  EXPECT_EQ(r.matched_points, 4u);
  EXPECT_DOUBLE_EQ(r.coverage(), 0.5);
  EXPECT_NEAR(r.mean, 0.15, 1e-12);
  o.radius = 0.15;
  r = computeCrispness(scans, o);
  EXPECT_EQ(r.matched_points, 2u);
  EXPECT_DOUBLE_EQ(r.coverage(), 0.25);
  EXPECT_NEAR(r.mean, 0.1, 1e-12);
  EXPECT_EQ(CrispnessResult{}.coverage(), 0.0);  // no points: no coverage, not a division by 0
}

TEST(CrispnessTest, RejectsBadInput) {
  auto scans = squareRoom(60, [](int) { return Eigen::Isometry2d::Identity(); });
  CrispnessOptions o;
  o.radius = 0.0;
  EXPECT_THROW(computeCrispness(scans, o), InputError);
  o = CrispnessOptions{};
  o.min_index_gap = 0;
  EXPECT_THROW(computeCrispness(scans, o), InputError);
  o = CrispnessOptions{};
  o.max_index_gap = 10;  // below min_index_gap 50
  EXPECT_THROW(computeCrispness(scans, o), InputError);
  scans[3].points[7].x() = NAN;
  EXPECT_THROW(computeCrispness(scans), InputError);
  EXPECT_EQ(computeCrispness({}).points, 0u);
}

TEST(CrispnessTest, PlanarPoseOfA3dPose) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(1, 2, 3);
  const Eigen::Isometry2d q = planarPose(p);
  EXPECT_NEAR(Eigen::Rotation2Dd(q.linear()).angle(), 0.7, 1e-12);
  EXPECT_TRUE(q.translation().isApprox(Eigen::Vector2d(1, 2)));
}

TEST(CrispnessTest, PlaceScansByTimestamp) {
  Trajectory traj;
  for (int i = 0; i < 3; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(i, 0, 0);
    traj.push_back(10.0 + i, p);
  }
  const std::vector<std::vector<Eigen::Vector2d>> pts = {{{1, 0}}, {{0, 1}}};
  const std::vector<PosedScan> placed = placeScans(pts, {10.001, 12.0}, traj, 0.01);
  ASSERT_EQ(placed.size(), 2u);
  EXPECT_TRUE((placed[0].pose * placed[0].points[0]).isApprox(Eigen::Vector2d(1, 0)));
  EXPECT_TRUE((placed[1].pose * placed[1].points[0]).isApprox(Eigen::Vector2d(2, 1)));
  EXPECT_THROW(placeScans(pts, {10.0, 11.5}, traj, 0.01), InputError);
  EXPECT_THROW(placeScans(pts, {10.0}, traj, 0.01), InputError);
}

}  // namespace
}  // namespace plugslam
