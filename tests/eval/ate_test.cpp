#include "plugslam/eval/ate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw, double pitch = 0.0) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

// A 3D helix with changing attitude, 0.1 s apart.
Trajectory helix(std::size_t n) {
  Trajectory t;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.2 * double(i);
    t.push_back(0.1 * double(i),
                pose(3 * std::cos(a), 3 * std::sin(a), 0.05 * double(i), a, 0.1 * std::sin(a)));
  }
  return t;
}

Trajectory transformed(const Trajectory& t, const Eigen::Isometry3d& T, double scale = 1.0) {
  Trajectory out;
  for (const StampedPose& p : t) {
    Eigen::Isometry3d q = T * p.pose;
    q.translation() = scale * q.translation();
    out.push_back(p.t, q);
  }
  return out;
}

TEST(AteTest, RigidCopyHasZeroErrorAfterSe3Alignment) {
  const Trajectory ref = helix(60);
  const Trajectory est = transformed(ref, pose(4, -2, 1, 0.7, 0.3));
  const AteResult r = computeAte(ref, est, {Alignment::SE3, {}});
  EXPECT_EQ(r.translation.count, 60u);
  EXPECT_LT(r.translation.rmse, 1e-9);
  EXPECT_LT(r.translation.max, 1e-9);
  EXPECT_LT(r.rotation_deg.max, 1e-6);
  EXPECT_NEAR(r.transform.scale, 1.0, 1e-12);
}

TEST(AteTest, TranslatedCopyWithoutAlignmentHasTheOffsetAsError) {
  const Trajectory ref = helix(30);
  const Trajectory est = transformed(ref, pose(1, 2, 2, 0.0));  // |(1, 2, 2)| = 3
  const AteResult r = computeAte(ref, est, {Alignment::None, {}});
  EXPECT_NEAR(r.translation.rmse, 3.0, 1e-12);
  EXPECT_NEAR(r.translation.mean, 3.0, 1e-12);
  EXPECT_NEAR(r.translation.std, 0.0, 1e-9);
  EXPECT_NEAR(r.rotation_deg.max, 0.0, 1e-9);
  // One associated pair per error, in time order (same timestamps: pose k with pose k).
  ASSERT_EQ(r.pairs.size(), r.translation_errors.size());
  ASSERT_EQ(r.pairs.size(), ref.size());
  for (size_t k = 0; k < r.pairs.size(); ++k) {
    EXPECT_EQ(r.pairs[k].ref, k);
    EXPECT_EQ(r.pairs[k].est, k);
  }
}

TEST(AteTest, RotatedCopyWithoutAlignmentHasKnownError) {
  // Poses on the unit circle turned by 90 deg about the origin: every point moves by sqrt(2) and
  // every attitude by 90 deg.
  Trajectory ref;
  for (int i = 0; i < 8; ++i) {
    const double a = M_PI / 4 * i;
    ref.push_back(i, pose(std::cos(a), std::sin(a), 0.0, a));
  }
  const Trajectory est = transformed(ref, pose(0, 0, 0, M_PI / 2));
  const AteResult r = computeAte(ref, est, {Alignment::None, {}});
  EXPECT_NEAR(r.translation.rmse, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.translation.min, std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(r.rotation_deg.mean, 90.0, 1e-9);
  EXPECT_LT(computeAte(ref, est, {Alignment::SE2, {}}).translation.max, 1e-9);
}

TEST(AteTest, Sim3RecoversScale) {
  const Trajectory ref = helix(40);
  const Trajectory est = transformed(ref, pose(-1, 3, 0.5, -0.4, 0.2), 0.25);
  const AteResult se3 = computeAte(ref, est, {Alignment::SE3, {}});
  EXPECT_GT(se3.translation.rmse, 0.5);
  const AteResult sim3 = computeAte(ref, est, {Alignment::Sim3, {}});
  EXPECT_NEAR(sim3.transform.scale, 4.0, 1e-9);
  EXPECT_LT(sim3.translation.rmse, 1e-9);
  EXPECT_LT(sim3.rotation_deg.max, 1e-6);
}

TEST(AteTest, Se2AlignsOnlyYawAndPlanarTranslation) {
  Trajectory ref;
  for (int i = 0; i < 20; ++i) ref.push_back(i, pose(0.5 * i, std::sin(0.3 * i), 0.0, 0.1 * i));
  // A planar motion plus a 0.2 m lift: SE2 removes the planar part and leaves the lift.
  const Trajectory est = transformed(ref, pose(5, -1, 0.2, 1.0));
  const AteResult se2 = computeAte(ref, est, {Alignment::SE2, {}});
  EXPECT_NEAR(se2.translation.rmse, 0.2, 1e-9);
  EXPECT_NEAR(se2.translation.std, 0.0, 1e-9);
  EXPECT_NEAR(se2.transform.rotation(2, 2), 1.0, 1e-12);
  EXPECT_LT(computeAte(ref, est, {Alignment::SE3, {}}).translation.rmse, 1e-9);
}

TEST(AteTest, AssociatesByTimeWithOffsetAndTolerance) {
  const Trajectory ref = helix(50);
  Trajectory est;  // every other pose, stamped 5 ms late and shifted by 10 s
  for (std::size_t i = 0; i < ref.size(); i += 2) est.push_back(ref[i].t + 10.005, ref[i].pose);
  AteOptions o{Alignment::None, {0.01, -10.0}};
  const AteResult r = computeAte(ref, est, o);
  EXPECT_EQ(r.translation.count, 25u);
  EXPECT_LT(r.translation.max, 1e-12);

  o.association.time_offset = 0.0;
  try {
    computeAte(ref, est, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no overlap: reference spans [0, 4.9], estimate spans "
                                         "[10.005, 14.805]"),
              std::string::npos)
        << e.what();
  }
}

TEST(AteTest, AssociationIsOneToOne) {
  Trajectory ref, est;
  ref.push_back(0.0, pose(0, 0, 0, 0));
  ref.push_back(1.0, pose(1, 0, 0, 0));
  est.push_back(0.990, pose(1, 0, 0, 0));
  est.push_back(0.999, pose(1, 0, 0, 0));  // closer to t=1: it wins
  est.push_back(1.004, pose(1, 0, 0, 0));
  const auto pairs = associate(ref, est, {0.01, 0.0});
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].ref, 1u);
  EXPECT_EQ(pairs[0].est, 1u);
}

TEST(AteTest, RejectsTooFewPairsAndBadNames) {
  Trajectory ref, est;
  ref.push_back(0.0, pose(0, 0, 0, 0));
  ref.push_back(1.0, pose(1, 0, 0, 0));
  est = ref;
  EXPECT_THROW(computeAte(ref, est, {Alignment::SE3, {}}), InputError);
  EXPECT_NO_THROW(computeAte(ref, est, {Alignment::SE2, {}}));
  EXPECT_EQ(parseAlignment("Sim3"), Alignment::Sim3);
  EXPECT_THROW(parseAlignment("affine"), InputError);
}

}  // namespace
}  // namespace plugslam
