#include "plugslam/eval/relations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"
#include "temp_dir.h"

namespace plugslam {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d planar(double x, double y, double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, 0.0);
  return p;
}

TEST(RelationsTest, HandComputedConsecutiveCase) {
  // Reference: (0,0), (1,0), (2,0), heading 0. Estimate: the middle pose is 0.1 m too far and
  // turned by 2 deg.
  Trajectory ref, est;
  for (int i = 0; i < 3; ++i) ref.push_back(i, planar(i, 0, 0));
  est.push_back(0, planar(0, 0, 0));
  est.push_back(1, planar(1.1, 0, 2 * kDeg));
  est.push_back(2, planar(2, 0, 0));
  const std::vector<Relation> rel = relationsFromTrajectory(ref, 0.0);
  ASSERT_EQ(rel.size(), 2u);
  const RelationResult r = evaluateRelations(est, rel);
  EXPECT_EQ(r.used, 2u);
  // Relation 0->1: E = (1.1, 0, 2deg) * (1, 0, 0)^-1, translation (1.1 - cos 2deg, -sin 2deg).
  const double e1 = std::hypot(1.1 - std::cos(2 * kDeg), -std::sin(2 * kDeg));
  // Relation 1->2: P1^-1 P2 = (R(-2deg) (0.9, 0), -2deg); minus (1, 0) rotated by -2deg.
  const Eigen::Vector2d rel12 = Eigen::Rotation2Dd(-2 * kDeg) * Eigen::Vector2d(0.9, 0.0);
  const Eigen::Vector2d e2v = rel12 - Eigen::Rotation2Dd(-2 * kDeg) * Eigen::Vector2d(1.0, 0.0);
  const double e2 = e2v.norm();  // = 0.1
  EXPECT_NEAR(e2, 0.1, 1e-12);
  EXPECT_NEAR(r.translation.mean, (e1 + e2) / 2, 1e-12);
  EXPECT_NEAR(r.translation.std, std::abs(e1 - e2) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.translation_sq.mean, (e1 * e1 + e2 * e2) / 2, 1e-12);
  EXPECT_NEAR(r.rotation_deg.mean, 2.0, 1e-9);
  EXPECT_NEAR(r.rotation_deg.std, 0.0, 1e-9);
  EXPECT_NEAR(r.rotation_sq_deg.mean, 4.0, 1e-9);
}

TEST(RelationsTest, PairsWithinDistancePlusConsecutive) {
  // A 4 x 4 m square driven with 1 m steps: 16 poses, the last one next to the first.
  Trajectory ref;
  int k = 0;
  for (int side = 0; side < 4; ++side) {
    for (int s = 0; s < 4; ++s, ++k) {
      const Eigen::Vector2d corner[4] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
      const Eigen::Vector2d dir = (corner[(side + 1) % 4] - corner[side]) / 4.0;
      const Eigen::Vector2d p = corner[side] + s * dir;
      ref.push_back(k, planar(p.x(), p.y(), side * M_PI / 2));
    }
  }
  EXPECT_EQ(relationsFromTrajectory(ref, 0.0).size(), 15u);
  // Within 1 m: the 15 consecutive pairs plus (15, 0) closing the loop.
  const std::vector<Relation> rel = relationsFromTrajectory(ref, 1.0);
  ASSERT_EQ(rel.size(), 16u);
  const bool closes_loop = std::any_of(rel.begin(), rel.end(), [](const Relation& r) {
    return r.t1 == 0.0 && r.t2 == 15.0 && std::abs(r.delta.translation().norm() - 1.0) < 1e-12;
  });
  EXPECT_TRUE(closes_loop);
  const RelationResult self = evaluateRelations(ref, rel);
  EXPECT_EQ(self.used, 16u);
  EXPECT_LT(self.translation.mean, 1e-12);
  EXPECT_LT(self.rotation_deg.mean, 1e-6);
}

TEST(RelationsTest, ReadsTheFreiburgFormat) {
  const plugslam::testing::TempDir dir;
  const std::string path = dir.write("a.relations",
                                     "1182.412 1182.612 0.2 -0.01 0 0 0 0.0872664626\n"
                                     "# comment\n"
                                     "1182.612 1183.012 0.1 0.0 0.0 0.1 -0.2 0.3\n");
  const std::vector<Relation> rel = readRelations(path);
  ASSERT_EQ(rel.size(), 2u);
  EXPECT_DOUBLE_EQ(rel[0].t1, 1182.412);
  EXPECT_DOUBLE_EQ(rel[0].t2, 1182.612);
  EXPECT_TRUE(rel[0].delta.translation().isApprox(Eigen::Vector3d(0.2, -0.01, 0)));
  EXPECT_NEAR(Eigen::AngleAxisd(rel[0].delta.linear()).angle(), 5 * kDeg, 1e-9);
  // roll, pitch, yaw compose as Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(rel[1].delta.linear().isApprox(expected, 1e-12));

  writeRelations(rel, dir.file("b.relations"));
  const std::vector<Relation> again = readRelations(dir.file("b.relations"));
  ASSERT_EQ(again.size(), 2u);
  EXPECT_TRUE(again[1].delta.isApprox(rel[1].delta, 1e-9));
  EXPECT_DOUBLE_EQ(again[1].t2, 1183.012);
}

TEST(RelationsTest, RejectsMalformedFilesAndMissingOverlap) {
  const plugslam::testing::TempDir dir;
  EXPECT_THROW(readRelations(dir.write("a", "1 2 0 0 0 0 0\n")), ParseError);
  EXPECT_THROW(readRelations(dir.write("b", "1 2 0 0 0 0 0 nan\n")), ParseError);
  EXPECT_THROW(readRelations(dir.write("c", "# nothing\n")), ParseError);
  Trajectory est;
  est.push_back(0.0, planar(0, 0, 0));
  est.push_back(1.0, planar(1, 0, 0));
  const std::vector<Relation> far = {Relation{100.0, 101.0, planar(1, 0, 0)}};
  try {
    evaluateRelations(est, far);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no overlap: relations span [100, 101], estimate spans "
                                         "[0, 1]"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace plugslam
