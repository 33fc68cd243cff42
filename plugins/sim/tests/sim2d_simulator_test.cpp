// sim2d simulator: determinism, odometry, presets, collisions, loops, exploration, speed.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>

#include "plugslam/errors.h"
#include "sim2d/simulator.h"
#include "temp_dir.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

std::vector<SimFrame> runAll(Simulator& sim) {
  std::vector<SimFrame> frames;
  SimFrame f;
  while (sim.step(f)) frames.push_back(f);
  return frames;
}

// Relative motion from pose a to pose b, expressed in a's frame.
Eigen::Vector3d between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  const Eigen::Vector2d d = b.head<2>() - a.head<2>();
  return Eigen::Vector3d(c * d.x() + s * d.y(), -s * d.x() + c * d.y(), wrapAngle(b.z() - a.z()));
}

double pointSegmentDistance(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d e = s.b - s.a;
  const double u = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  return (s.a + u * e - p).norm();
}

bool segmentsIntersect(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Segment& s) {
  auto orient = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
    return (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
  };
  const double d1 = orient(p, q, s.a), d2 = orient(p, q, s.b);
  const double d3 = orient(s.a, s.b, p), d4 = orient(s.a, s.b, q);
  return ((d1 > 0) != (d2 > 0) || d1 == 0 || d2 == 0) &&
         ((d3 > 0) != (d4 > 0) || d3 == 0 || d4 == 0);
}

TEST(Sim2dSimulator, SameSeedSameFramesOtherSeedDiffers) {
  Simulator a(presetSession("stage-0", 7)), b(presetSession("stage-0", 7));
  Simulator c(presetSession("stage-0", 8));
  const auto fa = runAll(a), fb = runAll(b), fc = runAll(c);
  ASSERT_EQ(fa.size(), fb.size());
  ASSERT_EQ(fa.size(), a.frameCount());
  size_t range_diff = 0;
  for (size_t i = 0; i < fa.size(); ++i) {
    EXPECT_EQ(fa[i].index, i);
    EXPECT_EQ(fa[i].time, fb[i].time);
    EXPECT_EQ(fa[i].ground_truth, fb[i].ground_truth);
    EXPECT_EQ(fa[i].odometry, fb[i].odometry);
    ASSERT_EQ(fa[i].lasers.size(), 2u);
    for (size_t l = 0; l < 2; ++l) {
      ASSERT_EQ(fa[i].lasers[l].ranges.size(), fb[i].lasers[l].ranges.size());
      for (size_t k = 0; k < fa[i].lasers[l].ranges.size(); ++k) {
        ASSERT_TRUE(sameBits(fa[i].lasers[l].ranges[k], fb[i].lasers[l].ranges[k]));
        range_diff += sameBits(fa[i].lasers[l].ranges[k], fc[i].lasers[l].ranges[k]) ? 0 : 1;
      }
    }
  }
  // The tour is seed-independent, the noise is not.
  ASSERT_EQ(fc.size(), fa.size());
  EXPECT_EQ(fc.back().ground_truth, fa.back().ground_truth);
  EXPECT_NE(fc.back().odometry, fa.back().odometry);
  EXPECT_GT(range_diff, fa.size() * 1000);

  // reset() replays the same frames.
  a.reset();
  SimFrame f;
  ASSERT_TRUE(a.step(f));
  ASSERT_TRUE(a.step(f));
  EXPECT_EQ(f.odometry, fa[1].odometry);
  EXPECT_TRUE(sameBits(f.lasers[0].ranges[500], fa[1].lasers[0].ranges[500]));
}

TEST(Sim2dSimulator, NoiselessOdometryEqualsGroundTruth) {
  SimConfig config = presetSession("stage-1", 3);
  config.odometry = OdometryNoise::none();
  config.lasers.clear();
  Simulator sim(config);
  const auto frames = runAll(sim);
  ASSERT_GT(frames.size(), 100u);
  for (size_t i = 1; i < frames.size(); ++i) {
    const Eigen::Vector3d gt = between(frames[i - 1].ground_truth, frames[i].ground_truth);
    const Eigen::Vector3d od = between(frames[i - 1].odometry, frames[i].odometry);
    ASSERT_NEAR((gt - od).norm(), 0.0, 1e-12) << "frame " << i;
    const double dth = (frames[i].wheel_right - frames[i].wheel_left) / config.drive.wheel_base;
    ASSERT_NEAR(wrapAngle(dth - gt.z()), 0.0, 1e-12);
  }
  EXPECT_EQ(frames.back().odometry, frames.back().ground_truth);
}

TEST(Sim2dSimulator, NoisyOdometryDriftsPlausibly) {
  Simulator sim(presetSession("stage-1", 3));
  const auto frames = runAll(sim);
  const Eigen::Vector3d err = between(frames.back().ground_truth, frames.back().odometry);
  const double position = err.head<2>().norm();
  std::cout << "stage-1 final odometry error: " << position << " m, " << err.z() * 180 / M_PI
            << " deg over " << sim.pathLength() << " m\n";
  EXPECT_GT(position, 0.01);
  EXPECT_LT(position, 0.05 * sim.pathLength());
  EXPECT_GT(std::abs(err.z()), 1e-4);
  EXPECT_LT(std::abs(err.z()), 0.35);
  // Relative motion per frame stays close to the truth (no jumps).
  for (size_t i = 1; i < frames.size(); ++i) {
    const Eigen::Vector3d gt = between(frames[i - 1].ground_truth, frames[i].ground_truth);
    const Eigen::Vector3d od = between(frames[i - 1].odometry, frames[i].odometry);
    ASSERT_LT((gt.head<2>() - od.head<2>()).norm(), 0.01);
    ASSERT_LT(std::abs(gt.z() - od.z()), 0.02);
  }
}

TEST(Sim2dSimulator, PresetsMatchSeedLengthsAndNeverCrossWalls) {
  for (const std::string& name : presetNames()) {
    Simulator sim(presetSession(name));
    const double seed_length = presetSeedLength(name);
    EXPECT_NEAR(sim.pathLength(), seed_length, 0.05 * seed_length) << name;
    const auto& gt = sim.groundTruth();
    EXPECT_EQ(gt.size(), sim.frameCount());
    double length = 0.0, min_clearance = 1e9;
    const auto& walls = sim.world().segments();
    for (size_t i = 1; i < gt.size(); ++i) {
      length += (gt[i].head<2>() - gt[i - 1].head<2>()).norm();
      // Speed limit respected.
      ASSERT_LE((gt[i].head<2>() - gt[i - 1].head<2>()).norm(), 0.5 / 10.0 + 1e-9) << name;
      for (const Segment& w : walls) {
        ASSERT_FALSE(segmentsIntersect(gt[i - 1].head<2>(), gt[i].head<2>(), w))
            << name << " frame " << i << " crosses a wall";
        min_clearance = std::min(min_clearance, pointSegmentDistance(gt[i].head<2>(), w));
      }
    }
    EXPECT_NEAR(length, sim.pathLength(), 0.01 * seed_length) << name;
    EXPECT_GE(min_clearance, sim.config().drive.robot_radius) << name;
    std::cout << name << ": " << sim.frameCount() << " frames, " << sim.pathLength() << " m (seed "
              << seed_length << " m), min clearance " << min_clearance << " m\n";
  }
}

TEST(Sim2dSimulator, LongSessionsRevisitPlaces) {
  for (const std::string name : {"stage-2", "stage-3"}) {
    Simulator sim(presetSession(name));
    const auto& gt = sim.groundTruth();
    // A revisit: within 1 m of a pose driven more than 60 s earlier.
    size_t revisits = 0;
    for (size_t i = 600; i < gt.size(); i += 10) {
      for (size_t j = 0; j + 600 < i; j += 5) {
        if ((gt[i].head<2>() - gt[j].head<2>()).norm() < 1.0) {
          ++revisits;
          break;
        }
      }
    }
    EXPECT_GT(revisits, 100u) << name;
  }
}

// Sum of n n^T over scan points (normals from neighbouring points, in the robot frame): its
// smallest eigenvalue counts the points constraining the worst translation direction.
Eigen::Matrix2d normalInformation(const LaserScan& scan) {
  std::vector<Eigen::Vector2d> p(scan.ranges.size());
  for (size_t i = 0; i < p.size(); ++i) {
    const double a = scan.angle_min + i * scan.angle_increment;
    p[i] = scan.ranges[i] * Eigen::Vector2d(std::cos(a), std::sin(a));
  }
  Eigen::Matrix2d h = Eigen::Matrix2d::Zero();
  const Eigen::Matrix2d r = Eigen::Rotation2Dd(scan.mount.z()).toRotationMatrix();
  for (size_t i = 2; i + 2 < p.size(); ++i) {
    if (!p[i - 2].allFinite() || !p[i].allFinite() || !p[i + 2].allFinite()) continue;
    const Eigen::Vector2d t = p[i + 2] - p[i - 2];
    if (t.norm() > 0.3 || t.norm() < 1e-9) continue;  // a depth jump, not a surface
    const Eigen::Vector2d n = r * Eigen::Vector2d(-t.y(), t.x()).normalized();
    h += n * n.transpose();
  }
  return h;
}

TEST(Sim2dSimulator, ScansConstrainBothAxesEverywhere) {
  // Corridors carry columns, doors and alcoves, so even a single laser is never degenerate.
  for (const std::string name : {"stage-1", "stage-3"}) {
    SimConfig config = presetSession(name);
    for (LaserConfig& l : config.lasers) {
      l.range_sigma = 0.0;
      l.dropout = 0.0;
    }
    Simulator sim(config);
    SimFrame f;
    double worst_front = 1e9, worst_both = 1e9;
    while (sim.step(f)) {
      if (f.index % 10 != 0) continue;
      const Eigen::Matrix2d front = normalInformation(f.lasers[0]);
      const Eigen::Matrix2d both = front + normalInformation(f.lasers[1]);
      worst_front = std::min(
          worst_front, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(front).eigenvalues()(0));
      worst_both = std::min(worst_both,
                            Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(both).eigenvalues()(0));
    }
    std::cout << name << ": weakest-axis information front " << worst_front << ", both "
              << worst_both << "\n";
    EXPECT_GT(worst_front, 25.0) << name;
    EXPECT_GT(worst_both, 60.0) << name;
  }
}

TEST(Sim2dSimulator, FramesCarryTheLaserDescription) {
  Simulator sim(presetSession("stage-0", 1));
  SimFrame f;
  ASSERT_TRUE(sim.step(f));
  EXPECT_EQ(f.index, 0u);
  EXPECT_EQ(f.time, 0.0);
  EXPECT_EQ(f.odometry, f.ground_truth);
  ASSERT_EQ(f.lasers.size(), 2u);
  EXPECT_EQ(f.lasers[0].name, "front_laser");
  EXPECT_EQ(f.lasers[1].name, "rear_laser");
  EXPECT_EQ(f.lasers[1].mount, Eigen::Vector3d(-0.2, 0.0, M_PI));
  EXPECT_DOUBLE_EQ(f.lasers[0].angle_min, -0.75 * M_PI);
  EXPECT_DOUBLE_EQ(f.lasers[0].angle_increment, 1.5 * M_PI / 1080);
  EXPECT_EQ(f.lasers[0].max_range, 30.0);
  ASSERT_EQ(f.lasers[0].ranges.size(), 1081u);
  size_t valid = 0;
  for (double r : f.lasers[0].ranges) valid += std::isfinite(r) ? 1 : 0;
  EXPECT_GT(valid, 1000u);
  ASSERT_TRUE(sim.step(f));
  EXPECT_NEAR(f.time, 0.1, 1e-15);
}

TEST(Sim2dSimulator, ExplorationIsDeterministicAndCollisionFree) {
  SimConfig config = presetSession("stage-0", 11);
  config.tour = {Eigen::Vector2d(31.25, 20.0)};
  config.path_length = 120.0;
  Simulator a(config), b(config);
  EXPECT_EQ(a.groundTruth(), b.groundTruth());
  EXPECT_GE(a.minClearance(), config.drive.robot_radius);
  EXPECT_NEAR(a.pathLength(), 120.0, 0.5);
  config.seed = 12;
  Simulator c(config);
  EXPECT_NE(a.groundTruth().back(), c.groundTruth().back());
}

TEST(Sim2dSimulator, DrivesInALoadedPgmWorld) {
  // A 12 x 8 m room at 0.1 m/pixel: 2-pixel thick outer walls, a 1 x 1 m block and an internal
  // wall with a 1.5 m gap.
  const int w = 120, h = 80;
  std::vector<int> img(w * h, 254);
  auto fill = [&](int c0, int r0, int c1, int r1) {
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) img[r * w + c] = 0;
  };
  fill(0, 0, w, 2);
  fill(0, h - 2, w, h);
  fill(0, 0, 2, h);
  fill(w - 2, 0, w, h);
  fill(30, 30, 40, 40);
  fill(70, 2, 72, 50);  // leaves rows 50..78 open
  const plugslam::testing::TempDir tmp;
  std::string pgm = "P2\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
  for (int v : img) pgm += std::to_string(v) + "\n";
  const std::string path = tmp.write("room.pgm", pgm);
  SimConfig config;
  config.world = std::make_shared<const World>(World::loadPgm(path, 0.1, Eigen::Vector2d(-1, -1)));
  config.tour = {Eigen::Vector2d(1.5, 5.0), Eigen::Vector2d(9.5, 5.0)};  // either side of the wall
  config.path_length = 60.0;
  config.lasers = defaultLasers();
  config.seed = 4;
  Simulator sim(config);
  EXPECT_NEAR(sim.pathLength(), 60.0, 0.1);
  EXPECT_GE(sim.minClearance(), config.drive.robot_radius);
  const auto& gt = sim.groundTruth();
  for (size_t i = 1; i < gt.size(); ++i) {
    ASSERT_FALSE(sim.world().crosses(gt[i - 1].head<2>(), gt[i].head<2>())) << "frame " << i;
  }
  // The robot reached the far side of the internal wall (x = 6.0 .. 6.2 m).
  double max_x = -1e9;
  for (const auto& p : gt) max_x = std::max(max_x, p.x());
  EXPECT_GT(max_x, 9.0);
  SimFrame f;
  ASSERT_TRUE(sim.step(f));
  size_t valid = 0;
  for (double r : f.lasers[0].ranges) valid += std::isfinite(r) ? 1 : 0;
  EXPECT_GT(valid, 1000u);  // a closed room: nearly every beam returns

  config.tour = {Eigen::Vector2d(1.5, 5.0)};  // exploration
  Simulator explorer(config);
  EXPECT_GE(explorer.minClearance(), config.drive.robot_radius);
}

TEST(Sim2dSimulator, RejectsBadConfigs) {
  EXPECT_THROW(presetSession("stage-9"), InputError);
  SimConfig config = presetSession("stage-0");
  config.tour = {Eigen::Vector2d(6, 13.25), Eigen::Vector2d(10, 12.0)};  // on a wall
  EXPECT_THROW(Simulator{config}, InputError);
  config = presetSession("stage-0");
  config.tour = {Eigen::Vector2d(6, 13.25), Eigen::Vector2d(200, 0)};  // outside
  EXPECT_THROW(Simulator{config}, InputError);
  config = presetSession("stage-0");
  config.lasers[1].name = config.lasers[0].name;
  EXPECT_THROW(Simulator{config}, InputError);
  config = presetSession("stage-0");
  config.lasers[0].beams = 0;
  EXPECT_THROW(Simulator{config}, InputError);
  config = presetSession("stage-0");
  config.world = nullptr;
  EXPECT_THROW(Simulator{config}, InputError);
}

// The speed is printed, not asserted: the machine is shared, and speed is a benchmark's business.
TEST(Sim2dSimulator, SimulationSpeedWithTwoLasers) {
  Simulator sim(presetSession("stage-1", 2));
  SimFrame f;
  size_t n = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (sim.step(f) && n < 1000) ++n;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double fps = n / s;
  std::cout << "two 1081-beam lasers + odometry: " << fps << " frames/s\n";
  RecordProperty("frames_per_second", std::to_string(fps));
  EXPECT_EQ(n, 1000u);
}

}  // namespace
}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
