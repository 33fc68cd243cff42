#include "plugslam/solver/initialization.h"

#include <gtest/gtest.h>

#include <random>

#include "plugslam/solver/optimizer.h"
#include "plugslam/solver/pose_factors.h"

using namespace plugslam;

namespace {

// A 3D grid-like trajectory with loop closures; measurements exact.
template <int D>
struct Grid {
  std::vector<std::conditional_t<D == 2, SE2, SE3>> truth;
  FactorGraph graph;
};

SE3 randomPose3(std::mt19937& rng, double rot) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vector6d v;
  v << 3 * u(rng), 3 * u(rng), 3 * u(rng), rot * u(rng), rot * u(rng), rot * u(rng);
  return se3(v);
}

}  // namespace

TEST(Initialization, ChordalRecoversNoiseFreeGraphs2D) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FactorGraph g;
  std::vector<SE2> truth;
  for (int k = 0; k < 50; ++k) {
    truth.push_back(se2(5 * u(rng), 5 * u(rng), 3 * u(rng)));
    g.addVariable<VariableSE2>(k, k == 0 ? truth[0] : SE2::Identity());
  }
  for (int k = 0; k < 50; ++k) {
    for (int j : {k + 1, k + 7}) {
      if (j >= 50) continue;
      g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(k), &g.get<VariableSE2>(j),
                                        truth[k].inverse() * truth[j]);
    }
  }
  initializeChordal(g);
  for (int k = 0; k < 50; ++k) {
    EXPECT_LT((g.get<VariableSE2>(k).estimate().matrix() - truth[k].matrix()).norm(), 1e-9) << k;
  }
  EXPECT_LT(seSyncObjective(g), 1e-15);
  EXPECT_LT(g.chi2(), 1e-15);
}

TEST(Initialization, ChordalRecoversNoiseFreeGraphs3DAndKeepsFixedPoses) {
  std::mt19937 rng(8);
  FactorGraph g;
  std::vector<SE3> truth;
  for (int k = 0; k < 40; ++k) {
    truth.push_back(randomPose3(rng, 2.0));
    g.addVariable<VariableSE3>(k, SE3::Identity());
  }
  // The anchor is the fixed variable 5, not the first one.
  g.get<VariableSE3>(5).setEstimate(truth[5]);
  g.get<VariableSE3>(5).setFixed(true);
  for (int k = 0; k < 40; ++k) {
    for (int j : {k + 1, k + 5}) {
      if (j >= 40) continue;
      g.emplaceFactor<BetweenFactorSE3>(&g.get<VariableSE3>(k), &g.get<VariableSE3>(j),
                                        truth[k].inverse() * truth[j]);
    }
  }
  initializeChordal(g);
  for (int k = 0; k < 40; ++k) {
    EXPECT_LT((g.get<VariableSE3>(k).estimate().matrix() - truth[k].matrix()).norm(), 1e-9) << k;
  }
}

TEST(Initialization, SpanningTreeComposesOdometry) {
  FactorGraph g;
  for (int k = 0; k < 4; ++k) g.addVariable<VariableSE2>(k, SE2::Identity());
  for (int k = 0; k < 3; ++k) {
    g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(k), &g.get<VariableSE2>(k + 1),
                                      se2(1, 0, M_PI / 2));
  }
  // A reversed edge to a fifth pose.
  g.addVariable<VariableSE2>(9, SE2::Identity());
  g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(9), &g.get<VariableSE2>(3), se2(2, 0, 0));
  EXPECT_EQ(initializeSpanningTree(g), 4u);
  const Eigen::Vector3d p3 = toVector(g.get<VariableSE2>(3).estimate());
  EXPECT_NEAR(p3.x(), 0.0, 1e-12);
  EXPECT_NEAR(p3.y(), 1.0, 1e-12);
  EXPECT_NEAR(normalizeAngle(p3.z() - 1.5 * M_PI), 0.0, 1e-12);
  EXPECT_LT(g.chi2(), 1e-20);
}

TEST(Initialization, ChordalThenGaussNewtonOnNoisyGraphBeatsOdometryStart) {
  // A long noisy loop with large heading noise: odometry drifts, chordal does not.
  const int n = 200;
  std::vector<SE2> truth;
  for (int k = 0; k < n; ++k) {
    const double a = 4.0 * M_PI * k / n;
    truth.push_back(se2(10 * std::cos(a), 10 * std::sin(a), a + M_PI / 2));
  }
  auto build = [&](FactorGraph& g, unsigned seed) {
    std::mt19937 r(seed);
    std::normal_distribution<double> d(0.0, 1.0);
    for (int k = 0; k < n; ++k) g.addVariable<VariableSE2>(k, SE2::Identity());
    const Eigen::Matrix3d inf = Eigen::Vector3d(100, 100, 400).asDiagonal();
    for (int k = 0; k < n; ++k) {
      for (int j : {k + 1, k + n / 2}) {
        if (j >= n) continue;
        const SE2 z = truth[k].inverse() * truth[j] * se2(0.1 * d(r), 0.1 * d(r), 0.05 * d(r));
        g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(k), &g.get<VariableSE2>(j), z, inf);
      }
    }
  };
  FactorGraph a, b;
  build(a, 3);
  build(b, 3);
  initializeChordal(a);
  initializeSpanningTree(b);
  EXPECT_LT(a.chi2(), b.chi2());
  OptimizerOptions o;
  o.algorithm = Algorithm::kGaussNewton;
  const OptimizeResult ra = Optimizer(o).optimize(a);
  EXPECT_TRUE(ra.ok());
  // Expected chi2 at the optimum is about (edges - dof) = 3 * (edges - poses + 1).
  const double dof = 3.0 * (double(a.numFactors()) - (n - 1));
  EXPECT_LT(ra.final_chi2, 2.0 * dof);
}
