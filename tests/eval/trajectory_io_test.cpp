#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <random>

#include "plugslam/errors.h"
#include "plugslam/trajectory.h"
#include "temp_dir.h"

namespace plugslam {
namespace {

using plugslam::testing::TempDir;

Trajectory randomTrajectory(std::size_t n, bool stamps_are_indices) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Trajectory traj;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    p.translation() = Eigen::Vector3d(100 * u(rng), 100 * u(rng), 10 * u(rng));
    traj.push_back(stamps_are_indices ? double(i) : 1305031102.160407 + 0.033 * double(i), p);
  }
  return traj;
}

void expectSame(const Trajectory& a, const Trajectory& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].t, b[i].t, 1e-6) << "pose " << i;
    EXPECT_TRUE(a[i].pose.isApprox(b[i].pose, tol)) << "pose " << i;
  }
}

// Returns the ParseError's line, failing the test if something else (or nothing) is thrown.
int parseErrorLine(const std::function<void()>& f, const std::string& expected_text) {
  try {
    f();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find(expected_text), std::string::npos) << e.what();
    return e.line();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected ParseError, got: " << e.what();
    return -1;
  }
  ADD_FAILURE() << "expected ParseError, nothing thrown";
  return -1;
}

TEST(TrajectoryTest, RejectsTimestampsThatDoNotIncrease) {
  Trajectory t;
  t.push_back(1.0, Eigen::Isometry3d::Identity());
  EXPECT_THROW(t.push_back(1.0, Eigen::Isometry3d::Identity()), InputError);
  EXPECT_THROW(t.push_back(0.5, Eigen::Isometry3d::Identity()), InputError);
  EXPECT_THROW(t.push_back(NAN, Eigen::Isometry3d::Identity()), InputError);
  EXPECT_EQ(t.size(), 1u);
}

TEST(TrajectoryTest, PathLengthNearestAndTransform) {
  Trajectory t;
  for (int i = 0; i < 4; ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(3.0 * i, 4.0 * i, 0.0);  // 5 m per step
    t.push_back(0.1 * i, p);
  }
  EXPECT_DOUBLE_EQ(t.pathLength(), 15.0);
  EXPECT_EQ(t.cumulativeDistances()[2], 10.0);
  EXPECT_EQ(t.nearest(0.19, 0.02).value(), 2u);
  EXPECT_EQ(t.nearest(0.0, 0.0).value(), 0u);
  EXPECT_FALSE(t.nearest(0.15, 0.01).has_value());
  EXPECT_FALSE(t.nearest(-1.0, 0.5).has_value());
  Eigen::Isometry3d shift = Eigen::Isometry3d::Identity();
  shift.translation() = Eigen::Vector3d(0, 0, 2);
  t.transform(shift);
  EXPECT_DOUBLE_EQ(t[3].pose.translation().z(), 2.0);
}

TEST(TrajectoryIoTest, TumRoundTrip) {
  const TempDir dir;
  const Trajectory a = randomTrajectory(50, false);
  writeTumTrajectory(a, dir.file("a.tum"));
  expectSame(a, readTumTrajectory(dir.file("a.tum")), 1e-8);
  expectSame(a, readTrajectory(dir.file("a.tum")), 1e-8);
  // The atomic write leaves nothing else behind.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);
}

TEST(TrajectoryIoTest, KittiRoundTripWithAndWithoutTimes) {
  const TempDir dir;
  const Trajectory a = randomTrajectory(20, false);
  writeKittiTrajectory(a, dir.file("poses.txt"), dir.file("times.txt"));
  expectSame(a, readKittiTrajectory(dir.file("poses.txt"), dir.file("times.txt")), 1e-9);
  const Trajectory by_index = readTrajectory(dir.file("poses.txt"));
  ASSERT_EQ(by_index.size(), 20u);
  EXPECT_EQ(by_index[0].t, 0.0);
  EXPECT_EQ(by_index[19].t, 19.0);
  EXPECT_TRUE(by_index[7].pose.isApprox(a[7].pose, 1e-9));
}

TEST(TrajectoryIoTest, KittiValuesAreRowMajor) {
  const TempDir dir;
  // 90 deg about z, translation (1, 2, 3).
  const std::string p = dir.write("k.txt", "0 -1 0 1 1 0 0 2 0 0 1 3\n");
  const Trajectory t = readKittiTrajectory(p);
  ASSERT_EQ(t.size(), 1u);
  EXPECT_TRUE(t[0].pose.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_TRUE((t[0].pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
}

TEST(TrajectoryIoTest, ReadsG2oVerticesSortedById) {
  const TempDir dir;
  const std::string se2 = dir.write("a.g2o",
                                    "VERTEX_SE2 2 2.0 0.5 1.5707963267948966\n"
                                    "VERTEX_SE2 0 0 0 0\n"
                                    "EDGE_SE2 0 2 1 0 0 1 0 0 1 0 1\n"
                                    "VERTEX_XY 10 1 2\n"
                                    "FIX 0\n");
  const Trajectory t = readTrajectory(se2);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].t, 0.0);
  EXPECT_EQ(t[1].t, 2.0);
  EXPECT_TRUE(t[1].pose.translation().isApprox(Eigen::Vector3d(2.0, 0.5, 0.0)));
  EXPECT_NEAR((t[1].pose.linear() * Eigen::Vector3d::UnitX()).y(), 1.0, 1e-12);

  const std::string se3 = dir.write("b.txt",
                                    "VERTEX_SE3:QUAT 5 1 2 3 0 0 0.7071067811865476 "
                                    "0.7071067811865476\n"
                                    "VERTEX_SE3:QUAT 4 0 0 0 0 0 0 1\n");
  EXPECT_EQ(detectTrajectoryFormat(se3), TrajectoryFormat::G2o);
  const Trajectory u = readTrajectory(se3);
  ASSERT_EQ(u.size(), 2u);
  EXPECT_EQ(u[0].t, 4.0);
  EXPECT_TRUE(u[1].pose.translation().isApprox(Eigen::Vector3d(1, 2, 3)));
}

TEST(TrajectoryIoTest, DetectsFormats) {
  const TempDir dir;
  EXPECT_EQ(detectTrajectoryFormat(dir.write("x.txt", "# c\n1 0 0 0 0 0 0 1\n")),
            TrajectoryFormat::Tum);
  EXPECT_EQ(detectTrajectoryFormat(dir.write("y.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n")),
            TrajectoryFormat::Kitti);
  EXPECT_EQ(detectTrajectoryFormat(dir.write("z.g2o", "")), TrajectoryFormat::G2o);
  EXPECT_EQ(detectTrajectoryFormat(dir.file("w.kitti")), TrajectoryFormat::Kitti);
  EXPECT_EQ(parseErrorLine([&] { detectTrajectoryFormat(dir.write("v.txt", "1 2 3\n")); },
                           "cannot detect"),
            1);
  EXPECT_EQ(parseTrajectoryFormat("TUM"), TrajectoryFormat::Tum);
  EXPECT_THROW(parseTrajectoryFormat("csv"), InputError);
}

TEST(TrajectoryIoTest, RejectsMalformedTum) {
  const TempDir dir;
  const std::string ok = "0 0 0 0 0 0 0 1\n";
  auto tum = [&](const std::string& text) {
    const std::string p = dir.write("t.tum", text);
    return [p] { readTumTrajectory(p); };
  };
  EXPECT_EQ(parseErrorLine(tum("# header\n" + ok + "1 0 0 0 0 0 1\n"), "expected 8 columns"), 3);
  EXPECT_EQ(parseErrorLine(tum(ok + "1 nan 0 0 0 0 0 1\n"), "finite"), 2);
  EXPECT_EQ(parseErrorLine(tum(ok + "1 0 inf 0 0 0 0 1\n"), "finite"), 2);
  EXPECT_EQ(parseErrorLine(tum(ok + "1 0 0 zero 0 0 0 1\n"), "expected a number"), 2);
  EXPECT_EQ(parseErrorLine(tum("5 0 0 0 0 0 0 1\n" + ok), "goes backwards"), 2);
  EXPECT_EQ(parseErrorLine(tum(ok + ok), "duplicate timestamp"), 2);
  EXPECT_EQ(parseErrorLine(tum("0 0 0 0 0 0 0 2\n"), "norm"), 1);
  EXPECT_EQ(parseErrorLine(tum(""), "no poses"), 0);
  EXPECT_EQ(parseErrorLine(tum("# only a comment\n\n"), "no poses"), 0);
  EXPECT_THROW(readTumTrajectory(dir.file("missing.tum")), InputError);
}

TEST(TrajectoryIoTest, RejectsMalformedKittiAndG2o) {
  const TempDir dir;
  const std::string id = "1 0 0 0 0 1 0 0 0 0 1 0\n";
  const std::string k1 = dir.write("k1.txt", id + "1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_EQ(parseErrorLine([&] { readKittiTrajectory(k1); }, "expected 12 columns"), 2);
  const std::string k2 = dir.write("k2.txt", id + "2 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_EQ(parseErrorLine([&] { readKittiTrajectory(k2); }, "not a rotation"), 2);
  const std::string k3 = dir.write("k3.txt", id + id);
  const std::string times = dir.write("times.txt", "0.0\n");
  EXPECT_THROW(readKittiTrajectory(k3, times), InputError);
  const std::string back = dir.write("back.txt", "1.0\n0.5\n");
  EXPECT_EQ(parseErrorLine([&] { readKittiTrajectory(k3, back); }, "goes backwards"), 2);

  const std::string g1 = dir.write("g1.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 0 1 0 0\n");
  EXPECT_EQ(parseErrorLine([&] { readG2oTrajectory(g1); }, "defined twice"), 2);
  const std::string g2 = dir.write("g2.g2o", "VERTEX_SE2 0 0 0\n");
  EXPECT_EQ(parseErrorLine([&] { readG2oTrajectory(g2); }, "expected 5 columns"), 1);
  const std::string g3 = dir.write("g3.g2o", "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\n");
  EXPECT_EQ(parseErrorLine([&] { readG2oTrajectory(g3); }, "no poses"), 0);
  const std::string g4 =
      dir.write("g4.g2o", "VERTEX_SE2 0 0 0 0\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n");
  EXPECT_EQ(parseErrorLine([&] { readG2oTrajectory(g4); }, "mixes"), 2);
  const std::string g5 = dir.write("g5.g2o", "VERTEX_SE2 1.5 0 0 0\n");
  EXPECT_EQ(parseErrorLine([&] { readG2oTrajectory(g5); }, "integer"), 1);
}

TEST(TrajectoryIoTest, WriteToMissingFolderIsAnInputError) {
  const TempDir dir;
  EXPECT_THROW(writeTumTrajectory(randomTrajectory(2, false), dir.file("no/such/dir/a.tum")),
               InputError);
}

}  // namespace
}  // namespace plugslam
