#include "plugslam/geometry.h"

#include <gtest/gtest.h>

#include <random>

using namespace plugslam;

TEST(Geometry, NormalizeAngleWrapsIntoHalfOpenRange) {
  EXPECT_DOUBLE_EQ(normalizeAngle(0.5), 0.5);
  EXPECT_NEAR(normalizeAngle(3.0 * M_PI), -M_PI, 1e-12);
  EXPECT_NEAR(normalizeAngle(-3.5 * M_PI), 0.5 * M_PI, 1e-12);
  EXPECT_NEAR(normalizeAngle(7.0), 7.0 - 2.0 * M_PI, 1e-12);
  for (double a = -20.0; a < 20.0; a += 0.37) {
    const double n = normalizeAngle(a);
    EXPECT_GE(n, -M_PI);
    EXPECT_LT(n, M_PI);
    EXPECT_NEAR(std::sin(n), std::sin(a), 1e-12);
    EXPECT_NEAR(std::cos(n), std::cos(a), 1e-12);
  }
}

TEST(Geometry, Se2VectorRoundTrip) {
  const SE2 t = se2(1.5, -2.0, 2.5);
  const Eigen::Vector3d v = toVector(t);
  EXPECT_NEAR(v.x(), 1.5, 1e-15);
  EXPECT_NEAR(v.y(), -2.0, 1e-15);
  EXPECT_NEAR(v.z(), 2.5, 1e-15);
  const SE2 c = se2(1.0, 0.0, M_PI / 2) * se2(1.0, 0.0, 0.0);
  EXPECT_NEAR(c.translation().x(), 1.0, 1e-15);
  EXPECT_NEAR(c.translation().y(), 1.0, 1e-15);
}

TEST(Geometry, So3ExpLogAreInverse) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 200; ++k) {
    Eigen::Vector3d w(u(rng), u(rng), u(rng));
    w *= (k % 4 == 0 ? 1e-9 : 3.0) / std::max(w.norm(), 1e-12) * std::abs(u(rng));
    const Eigen::Matrix3d r = so3Exp(w);
    EXPECT_NEAR((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
    EXPECT_LT((so3Log(r) - w).norm(), 1e-9) << w.transpose();
    EXPECT_LT((r - Eigen::Matrix3d(Eigen::AngleAxisd(w.norm(), w.normalized()))).norm(),
              k % 4 == 0 ? 1e-8 : 1e-12);
  }
  // Near pi the log is still accurate.
  const Eigen::Vector3d w(0.0, M_PI - 1e-7, 0.0);
  EXPECT_LT((so3Log(so3Exp(w)) - w).norm(), 1e-6);
}

TEST(Geometry, Se3SixVectorAndQuaternion) {
  Vector6d v;
  v << 1.0, -2.0, 0.5, 0.3, -0.2, 1.1;
  const SE3 x = se3(v);
  EXPECT_LT((toVector(x) - v).norm(), 1e-12);
  const Eigen::Quaterniond q = quaternionOf(x);
  EXPECT_GE(q.w(), 0.0);
  const SE3 y = se3(x.translation(), q);
  EXPECT_LT((y.matrix() - x.matrix()).norm(), 1e-12);
  // A negative-w quaternion gives the same rotation.
  const SE3 z = se3(x.translation(), Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()));
  EXPECT_LT((z.matrix() - x.matrix()).norm(), 1e-12);
}

TEST(Geometry, ProjectionsGiveRotations) {
  Eigen::Matrix3d m = so3Exp(Eigen::Vector3d(0.2, -0.4, 0.9));
  m += 0.01 * Eigen::Matrix3d::Ones();
  const Eigen::Matrix3d r = projectToSO3(m);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_NEAR((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 0.0, 1e-12);
  EXPECT_LT((r - so3Exp(Eigen::Vector3d(0.2, -0.4, 0.9))).norm(), 0.05);
  const Eigen::Matrix2d r2 = projectToSO2(2.0 * rotation2(0.7));
  EXPECT_NEAR(angleOf(r2), 0.7, 1e-12);
  // A reflection projects to a proper rotation.
  EXPECT_NEAR(projectToSO3(Eigen::Vector3d(1, 1, -1).asDiagonal()).determinant(), 1.0, 1e-12);
}
