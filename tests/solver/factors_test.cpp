#include <gtest/gtest.h>

#include <random>

#include "plugslam/errors.h"
#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/jacobian_check.h"
#include "plugslam/solver/pose_factors.h"
#include "plugslam/solver/projection_factors.h"
#include "plugslam/solver/registration_factors.h"

using namespace plugslam;

namespace {

std::mt19937 rng(42);
double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
SE2 randomSE2() { return se2(uniform(-5, 5), uniform(-5, 5), uniform(-3.0, 3.0)); }
SE3 randomSE3() {
  Vector6d v;
  for (int k = 0; k < 3; ++k) v[k] = uniform(-5, 5);
  for (int k = 3; k < 6; ++k) v[k] = uniform(-1.5, 1.5);
  return se3(v);
}
Eigen::Vector3d randomPoint3() {
  return Eigen::Vector3d(uniform(-3, 3), uniform(-3, 3), uniform(-3, 3));
}
Eigen::Vector2d randomPoint2() { return Eigen::Vector2d(uniform(-3, 3), uniform(-3, 3)); }

template <class M>
M randomInformation() {
  M a = M::Random();
  return a * a.transpose() + M::Identity();
}

// A factor without an analytic Jacobian: the numeric fallback must be used.
class RangeFactor final : public Factor<1, VariablePoint2> {
 public:
  RangeFactor(VariablePoint2* p, const Eigen::Vector2d& anchor, double range)
      : Factor(p), anchor_(anchor), range_(range) {}
  ErrorVector error() const override {
    return ErrorVector((var<0>()->estimate() - anchor_).norm() - range_);
  }

 private:
  Eigen::Vector2d anchor_;
  double range_;
};

// A factor whose analytic Jacobian is wrong on purpose: the checker must catch it.
class WrongJacobianFactor final : public Factor<2, VariablePoint2> {
 public:
  explicit WrongJacobianFactor(VariablePoint2* p) : Factor(p) {}
  ErrorVector error() const override { return 2.0 * var<0>()->estimate(); }
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override {
    e = error();
    J = Eigen::Matrix2d::Identity();
  }
};

}  // namespace

TEST(Factors, BetweenSE2Jacobian) {
  FactorGraph g;
  auto& a = g.addVariable<VariableSE2>(0, randomSE2());
  auto& b = g.addVariable<VariableSE2>(1, randomSE2());
  for (int k = 0; k < 20; ++k) {
    a.setEstimate(randomSE2());
    b.setEstimate(randomSE2());
    BetweenFactorSE2 f(&a, &b, randomSE2(), randomInformation<Eigen::Matrix3d>());
    // Central differences jump where the wrapped angle error crosses +-pi.
    if (std::abs(f.error()[2]) > 3.0) continue;
    const auto r = checkJacobian(f);
    EXPECT_TRUE(r.ok) << r;
    ASSERT_EQ(r.max_abs_error.size(), 2u);
  }
}

TEST(Factors, BetweenSE3Jacobian) {
  FactorGraph g;
  auto& a = g.addVariable<VariableSE3>(0, randomSE3());
  auto& b = g.addVariable<VariableSE3>(1, randomSE3());
  for (int k = 0; k < 20; ++k) {
    a.setEstimate(randomSE3());
    b.setEstimate(randomSE3());
    BetweenFactorSE3 f(&a, &b, randomSE3(), randomInformation<Eigen::Matrix<double, 6, 6>>());
    const auto r = checkJacobian(f);
    EXPECT_TRUE(r.ok) << r;
  }
}

TEST(Factors, PriorJacobians) {
  FactorGraph g;
  auto& a = g.addVariable<VariableSE2>(0, randomSE2());
  auto& b = g.addVariable<VariableSE3>(1, randomSE3());
  for (int k = 0; k < 20; ++k) {
    a.setEstimate(randomSE2());
    b.setEstimate(randomSE3());
    PriorFactorSE2 f2(&a, randomSE2());
    if (std::abs(f2.error()[2]) < 3.0) {
      const auto r2 = checkJacobian(f2);
      EXPECT_TRUE(r2.ok) << r2;
    }
    PriorFactorSE3 f3(&b, randomSE3());
    const auto r3 = checkJacobian(f3);
    EXPECT_TRUE(r3.ok) << r3;
  }
}

TEST(Factors, RegistrationJacobians) {
  FactorGraph g;
  auto& t2 = g.addVariable<VariableSE2>(0, randomSE2());
  auto& t3 = g.addVariable<VariableSE3>(1, randomSE3());
  for (int k = 0; k < 20; ++k) {
    t2.setEstimate(randomSE2());
    t3.setEstimate(randomSE3());
    PointToPointFactor2D a(&t2, randomPoint2(), randomPoint2());
    PointToLineFactor2D b(&t2, randomPoint2(), randomPoint2(), randomPoint2().normalized());
    PointToPointFactor3D c(&t3, randomPoint3(), randomPoint3());
    PointToPlaneFactor3D d(&t3, randomPoint3(), randomPoint3(), randomPoint3().normalized());
    for (const FactorBase* f :
         {static_cast<const FactorBase*>(&a), static_cast<const FactorBase*>(&b),
          static_cast<const FactorBase*>(&c), static_cast<const FactorBase*>(&d)}) {
      const auto r = checkJacobian(*f);
      EXPECT_TRUE(r.ok) << r;
    }
  }
}

TEST(Factors, ProjectionJacobians) {
  FactorGraph g;
  auto& pose = g.addVariable<VariableSE3>(0, SE3::Identity());
  auto& point = g.addVariable<VariablePoint3>(1, Eigen::Vector3d::Zero());
  PinholeCamera cam{718.856, 718.856, 607.19, 185.21, 0.537};
  for (int k = 0; k < 20; ++k) {
    pose.setEstimate(randomSE3());
    // A landmark in front of the camera.
    const Eigen::Vector3d pc(uniform(-2, 2), uniform(-2, 2), uniform(2, 20));
    point.setEstimate(pose.estimate() * pc);
    ReprojectionFactor mono(&pose, &point, Eigen::Vector2d(600, 180), cam);
    StereoFactor stereo(&pose, &point, Eigen::Vector3d(600, 180, 560), cam);
    const auto r1 = checkJacobian(mono, 1e-5);
    EXPECT_TRUE(r1.ok) << r1;
    const auto r2 = checkJacobian(stereo, 1e-5);
    EXPECT_TRUE(r2.ok) << r2;
  }
}

TEST(Factors, StereoErrorIsZeroForConsistentObservation) {
  FactorGraph g;
  auto& pose = g.addVariable<VariableSE3>(0, randomSE3());
  const Eigen::Vector3d pc(0.5, -0.2, 8.0);
  auto& point = g.addVariable<VariablePoint3>(1, pose.estimate() * pc);
  PinholeCamera cam{500, 510, 320, 240, 0.12};
  const Eigen::Vector3d z(500 * 0.5 / 8 + 320, 510 * -0.2 / 8 + 240, 500 * (0.5 - 0.12) / 8 + 320);
  StereoFactor f(&pose, &point, z, cam);
  EXPECT_LT(f.error().norm(), 1e-9);
}

TEST(Factors, NumericFallbackIsUsedAndChecked) {
  FactorGraph g;
  auto& p = g.addVariable<VariablePoint2>(0, Eigen::Vector2d(1.0, 2.0));
  RangeFactor f(&p, Eigen::Vector2d(0.0, 0.0), 1.0);
  Eigen::VectorXd e;
  Eigen::MatrixXd j;
  f.evaluate(e, j);
  const Eigen::Vector2d expected = Eigen::Vector2d(1.0, 2.0).normalized();
  EXPECT_NEAR(j(0, 0), expected.x(), 1e-8);
  EXPECT_NEAR(j(0, 1), expected.y(), 1e-8);
  EXPECT_TRUE(checkJacobian(f).ok);
}

TEST(Factors, CheckerCatchesAWrongJacobian) {
  FactorGraph g;
  auto& p = g.addVariable<VariablePoint2>(0, Eigen::Vector2d(1.0, 2.0));
  WrongJacobianFactor f(&p);
  const auto r = checkJacobian(f);
  EXPECT_FALSE(r.ok);
  ASSERT_EQ(r.max_abs_error.size(), 1u);
  EXPECT_NEAR(r.max_abs_error[0], 1.0, 1e-6);
  EXPECT_NE(r.describe().find("MISMATCH"), std::string::npos);
}

TEST(RobustKernels, DerivativesMatchNumeric) {
  for (const auto& name : robustKernelNames()) {
    auto k = makeRobustKernel(name, 1.3);
    for (double s : {0.1, 0.9, 1.5, 2.0, 5.0, 40.0}) {
      const double h = 1e-6;
      const Eigen::Vector3d r = k->robustify(s);
      const double d1 = (k->robustify(s + h)[0] - k->robustify(s - h)[0]) / (2 * h);
      if (name == "sdk.DCS") {
        // DCS reports the IRLS weight w^2, not d rho / ds, by design.
        EXPECT_LE(r[1], 1.0);
        EXPECT_NEAR(r[0], r[1] * s, 1e-12);
        continue;
      }
      EXPECT_NEAR(r[1], d1, 1e-5) << name << " s=" << s;
      EXPECT_LE(r[0], s + 1e-12) << name;
    }
    EXPECT_NEAR(k->robustify(1e-8)[1], 1.0, 1e-6) << name;  // quadratic near zero
  }
}

TEST(RobustKernels, FactoryAcceptsNamesAndRejectsUnknown) {
  EXPECT_STREQ(makeRobustKernel("Huber", 1.0)->name(), "sdk.Huber");
  EXPECT_STREQ(makeRobustKernel("sdk.cauchy", 2.0)->name(), "sdk.Cauchy");
  EXPECT_DOUBLE_EQ(makeRobustKernel("sdk.Tukey", 2.0)->scale(), 2.0);
  EXPECT_STREQ(makeRobustKernel("dcs", 1.0)->name(), "sdk.DCS");
  try {
    makeRobustKernel("Welsch", 1.0);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("sdk.Huber"), std::string::npos);
  }
  EXPECT_THROW(makeRobustKernel("Huber", -1.0), InputError);
  EXPECT_THROW(makeRobustKernel("Huber", std::nan("")), InputError);
}

TEST(FactorGraphTest, RejectsDuplicateIdsAndForeignVariables) {
  FactorGraph g, other;
  auto& a = g.addVariable<VariableSE2>(1, SE2::Identity());
  EXPECT_THROW(g.addVariable<VariableSE2>(1, SE2::Identity()), InputError);
  auto& foreign = other.addVariable<VariableSE2>(2, SE2::Identity());
  EXPECT_THROW(g.emplaceFactor<BetweenFactorSE2>(&a, &foreign, SE2::Identity()), InputError);
  EXPECT_THROW(g.emplaceFactor<BetweenFactorSE2>(&a, &a, SE2::Identity()), InputError);
  EXPECT_EQ(&g.get<VariableSE2>(1), &a);
  EXPECT_EQ(&g.get(VariableId<VariableSE2>{1}), &a);
  EXPECT_THROW(g.get<VariableSE3>(1), InputError);
  EXPECT_THROW(g.get<VariableSE2>(7), InputError);
}
