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
  // turned by 2 deg. The error is the benchmark's E = delta^-1 * (P1^-1 P2).
  Trajectory ref, est;
  for (int i = 0; i < 3; ++i) ref.push_back(i, planar(i, 0, 0));
  est.push_back(0, planar(0, 0, 0));
  est.push_back(1, planar(1.1, 0, 2 * kDeg));
  est.push_back(2, planar(2, 0, 0));
  const std::vector<Relation> rel = relationsFromTrajectory(ref, 0.0);
  ASSERT_EQ(rel.size(), 2u);
  const RelationResult r = evaluateRelations(est, rel);
  EXPECT_EQ(r.used, 2u);
  // Relation 0->1: E = (1, 0, 0)^-1 * (1.1, 0, 2deg): translation (0.1, 0).
  const double e1 = 0.1;
  // Relation 1->2: P1^-1 P2 = (R(-2deg) (0.9, 0), -2deg), delta = (1, 0, 0): translation
  // R(-2deg) (0.9, 0) - (1, 0), |.|^2 = 0.81 - 1.8 cos 2deg + 1.
  const double e2 = std::sqrt(0.81 - 1.8 * std::cos(2 * kDeg) + 1.0);
  EXPECT_NEAR(e2, 0.10534, 1e-5);
  EXPECT_NEAR(r.translation.mean, (e1 + e2) / 2, 1e-12);
  EXPECT_NEAR(r.translation.std, std::abs(e1 - e2) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.translation_sq.mean, (e1 * e1 + e2 * e2) / 2, 1e-12);
  EXPECT_NEAR(r.rotation_deg.mean, 2.0, 1e-9);
  EXPECT_NEAR(r.rotation_deg.std, 0.0, 1e-9);
  EXPECT_NEAR(r.rotation_sq_deg.mean, 4.0, 1e-9);
}

TEST(RelationsTest, ErrorIsTheRelationsInverseTimesTheEstimatesMotion) {
  // Estimate motion (0, 1, 180deg), relation (0.03, 0.96, 177deg). The benchmark's error
  // delta^-1 * m has translation R(-177deg) ((0, 1) - (0.03, 0.96)), |.| = 0.05, and 3 deg; the
  // other order m * delta^-1 would give |(0, 1) + R(3deg) (-0.03, -0.96)| = 0.0446.
  const Relation r{0, 1, planar(0.03, 0.96, 177 * kDeg)};
  const Eigen::Isometry3d e = relationError(r, planar(0, 0, 0), planar(0, 1, M_PI));
  EXPECT_NEAR(e.translation().norm(), 0.05, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(e.linear()).angle(), 3 * kDeg, 1e-12);
}

// A relations file as the benchmark publishes it, with scan stamps to the microsecond, against
// an estimate with poses at
//   1000.000001 (0, 0, 0deg)   1000.100002 (1, 0, 90deg)
//   1000.200003 (1, 1, 90deg)  1000.300004 (0, 1, 180deg)
// Errors E = delta^-1 * (P1^-1 P2), by hand:
//   a) t1 .000001 t2 .100002, delta (1.1, 0, 90deg): motion (1, 0, 90deg), |t(E)| =
//      |(1, 0) - (1.1, 0)| = 0.1, angle 0.
//   b) t1 .100002 t2 .200003, delta (1, 0, 2deg): motion R(-90deg) (0, 1) = (1, 0), 0deg:
//      |t(E)| = 0, angle 2deg.
//   c) t1 .000001 t2 .300004, delta (0.03, 0.96, 177deg): motion (0, 1, 180deg): |t(E)| =
//      |(-0.03, 0.04)| = 0.05, angle 3deg.
//   d) t2 1000.400005 has no pose; e) t1 1000.101002 is 1 ms after a pose (a neighbouring scan,
//      not its own); f) neither stamp has a pose.
// Used: a, b, c. Translation 0.1, 0, 0.05: mean 0.05, sample std sqrt((0.05^2 + 0.05^2) / 2) =
// 0.05; squares 0.01, 0, 0.0025: mean 0.0125 / 3. Rotation 0, 2, 3 deg: mean 5/3, sample std
// sqrt(((5/3)^2 + (1/3)^2 + (4/3)^2) / 2) = sqrt(7/3); squares 0, 4, 9: mean 13/3.
const char* kHandRelations =
    "1000.000001 1000.100002 1.1 0 0 0 0 1.5707963267948966\n"
    "1000.100002 1000.200003 1 0 0 0 0 0.034906585039886591\n"
    "1000.000001 1000.300004 0.03 0.96 0 0 0 3.0892327760299634\n"
    "1000.000001 1000.400005 1 0 0 0 0 0\n"
    "1000.101002 1000.200003 1 0 0 0 0 0\n"
    "2000 2001 1 0 0 0 0 0\n";

Trajectory handEstimate() {
  Trajectory est;
  est.push_back(1000.000001, planar(0, 0, 0));
  est.push_back(1000.100002, planar(1, 0, M_PI / 2));
  est.push_back(1000.200003, planar(1, 1, M_PI / 2));
  est.push_back(1000.300004, planar(0, 1, M_PI));
  return est;
}

TEST(RelationsTest, HandComputedRelationsFile) {
  const plugslam::testing::TempDir dir;
  const std::vector<Relation> rel = readRelations(dir.write("hand.relations", kHandRelations));
  ASSERT_EQ(rel.size(), 6u);
  const RelationResult r = evaluateRelations(handEstimate(), rel);
  EXPECT_EQ(r.relations, 6u);
  EXPECT_EQ(r.used, 3u);
  EXPECT_EQ(r.missing_t1, 1u);
  EXPECT_EQ(r.missing_t2, 1u);
  EXPECT_EQ(r.missing_both, 1u);
  EXPECT_LT(r.largest_dt, 1e-6);
  EXPECT_NEAR(r.translation.mean, 0.05, 1e-12);
  EXPECT_NEAR(r.translation.std, 0.05, 1e-12);
  EXPECT_NEAR(r.translation_sq.mean, 0.0125 / 3, 1e-12);
  EXPECT_NEAR(r.rotation_deg.mean, 5.0 / 3, 1e-9);
  EXPECT_NEAR(r.rotation_deg.std, std::sqrt(7.0 / 3), 1e-9);
  EXPECT_NEAR(r.rotation_sq_deg.mean, 13.0 / 3, 1e-9);
  // A tolerance as wide as a scan period would take relation e's neighbouring scan instead.
  const RelationResult wide = evaluateRelations(handEstimate(), rel, {0.01});
  EXPECT_EQ(wide.used, 4u);
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
