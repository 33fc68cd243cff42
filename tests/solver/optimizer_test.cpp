#include "plugslam/solver/optimizer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "plugslam/solver/pose_factors.h"
#include "plugslam/solver/projection_factors.h"
#include "plugslam/solver/registration_factors.h"

using namespace plugslam;

namespace {

// A square-ish loop of n poses with odometry and one loop closure; noise-free measurements come
// from the truth, so the optimum has chi2 = 0 at the truth (up to the gauge, fixed at pose 0).
struct Loop2D {
  std::vector<SE2> truth;
  FactorGraph graph;
  Loop2D(int n, double noise, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> nd(0.0, 1.0);
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * M_PI * k / n;
      truth.push_back(se2(5.0 * std::cos(a), 5.0 * std::sin(a), a + M_PI / 2));
    }
    for (int k = 0; k < n; ++k) {
      // Start from a corrupted guess.
      const SE2 guess = truth[k] * se2(0.3 * nd(rng), 0.3 * nd(rng), 0.1 * nd(rng));
      graph.addVariable<VariableSE2>(k, k == 0 ? truth[0] : guess);
    }
    for (int k = 0; k < n; ++k) {
      const int j = (k + 1) % n;
      const SE2 z = truth[k].inverse() * truth[j] *
                    se2(noise * nd(rng), noise * nd(rng), noise * 0.1 * nd(rng));
      graph.emplaceFactor<BetweenFactorSE2>(&graph.get<VariableSE2>(k), &graph.get<VariableSE2>(j),
                                            z, Eigen::Vector3d(10, 10, 100).asDiagonal());
    }
  }
};

}  // namespace

TEST(Optimizer, NoiseFreeLoopReachesTheTruth) {
  for (Algorithm alg : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt}) {
    Loop2D loop(40, 0.0, 1);
    OptimizerOptions o;
    o.algorithm = alg;
    o.dense_threshold = 0;  // force the sparse CHOLMOD path
    Optimizer opt(o);
    const OptimizeResult r = opt.optimize(loop.graph);
    EXPECT_TRUE(r.ok()) << toString(r.reason);
    EXPECT_FALSE(r.dense);
    EXPECT_EQ(r.system_size, 39 * 3);  // first pose fixes the gauge
    EXPECT_LT(r.final_chi2, 1e-12);
    EXPECT_GT(r.initial_chi2, 1.0);
    for (int k = 0; k < 40; ++k) {
      const SE2& e = loop.graph.get<VariableSE2>(k).estimate();
      EXPECT_LT((e.matrix() - loop.truth[k].matrix()).norm(), 1e-6) << k;
    }
    ASSERT_EQ(int(r.stats.size()), r.iterations);
    EXPECT_NEAR(r.stats.back().chi2, r.final_chi2, 1e-12);
  }
}

TEST(Optimizer, GaussNewtonAndLevenbergMarquardtAgreeOnNoisyLoop) {
  Loop2D a(60, 0.05, 7), b(60, 0.05, 7);
  OptimizerOptions o;
  o.algorithm = Algorithm::kGaussNewton;
  const OptimizeResult ra = Optimizer(o).optimize(a.graph);
  o.algorithm = Algorithm::kLevenbergMarquardt;
  Optimizer lm(o);
  int callbacks = 0;
  lm.setIterationCallback([&](const IterationStats& s) {
    ++callbacks;
    EXPECT_GE(s.lambda, 0.0);
    EXPECT_LE(s.chi2, s.chi2_before + 1e-9);  // LM never accepts an increase
  });
  const OptimizeResult rb = lm.optimize(b.graph);
  EXPECT_EQ(callbacks, rb.iterations);
  EXPECT_TRUE(ra.ok());
  EXPECT_TRUE(rb.ok());
  EXPECT_GT(ra.final_chi2, 0.0);
  EXPECT_NEAR(ra.final_chi2, rb.final_chi2, 1e-6 * ra.final_chi2);
  EXPECT_LT(ra.final_chi2, 1e-3 * ra.initial_chi2);
}

TEST(Optimizer, DenseAndSparsePathsAgree) {
  Loop2D a(8, 0.05, 3), b(8, 0.05, 3);
  OptimizerOptions o;
  o.dense_threshold = 1000;
  const OptimizeResult ra = Optimizer(o).optimize(a.graph);
  o.dense_threshold = 0;
  for (Factorization f : {Factorization::kSupernodal, Factorization::kSimplicial,
                          Factorization::kBlock, Factorization::kAuto}) {
    Loop2D c(8, 0.05, 3);
    o.factorization = f;
    const OptimizeResult rc = Optimizer(o).optimize(c.graph);
    EXPECT_FALSE(rc.dense);
    EXPECT_NEAR(ra.final_chi2, rc.final_chi2, 1e-9 * (1.0 + ra.final_chi2));
  }
  EXPECT_TRUE(ra.dense);
}

TEST(Optimizer, FixedVariablesStayPut) {
  Loop2D loop(10, 0.05, 5);
  auto& v3 = loop.graph.get<VariableSE2>(3);
  const SE2 before = v3.estimate();
  v3.setFixed(true);
  const OptimizeResult r = Optimizer().optimize(loop.graph);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.system_size, 9 * 3);  // only the explicit fix, no implicit gauge
  EXPECT_EQ(v3.estimate().matrix(), before.matrix());
}

TEST(Optimizer, PointToLineAlignmentRecoversTheTransform) {
  // Points on the walls of a room, seen from an unknown pose.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-4.0, 4.0);
  const SE2 truth = se2(0.3, -0.2, 0.15);
  FactorGraph g;
  auto& t = g.addVariable<VariableSE2>(0, SE2::Identity());
  auto build = [&] {
    g.clearFactors();
    for (int k = 0; k < 500; ++k) {
      Eigen::Vector2d q, n;
      switch (k % 4) {
        case 0:
          q << 5.0, u(rng);
          n << -1, 0;
          break;
        case 1:
          q << -5.0, u(rng);
          n << 1, 0;
          break;
        case 2:
          q << u(rng), 4.0;
          n << 0, -1;
          break;
        default:
          q << u(rng), -4.0;
          n << 0, 1;
          break;
      }
      const Eigen::Vector2d p = truth.inverse() * q;
      g.emplaceFactor<PointToLineFactor2D>(&t, p, q, n);
    }
  };
  build();
  Optimizer opt;
  const OptimizeResult r = opt.optimize(g);
  EXPECT_TRUE(r.ok()) << toString(r.reason);
  EXPECT_TRUE(r.dense);
  EXPECT_LT((toVector(t.estimate()) - toVector(truth)).norm(), 1e-9);

  // Per-frame cost of the aligner's use: one SE2, 500 point-to-line factors, fresh each frame.
  const int frames = 200;
  const auto t0 = std::chrono::steady_clock::now();
  int iterations = 0;
  for (int f = 0; f < frames; ++f) {
    t.setEstimate(SE2::Identity());
    iterations += opt.optimize(g).iterations;
  }
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("aligner-sized solve: %.1f us per frame (%.1f iterations), %.0f Hz\n",
              1e6 * dt / frames, double(iterations) / frames, frames / dt);
  RecordProperty("aligner_solve_us", int(1e6 * dt / frames));
}

TEST(Optimizer, SingularSystemIsReportedWithoutNaN) {
  // All lines parallel: translation along them is unobservable.
  FactorGraph g;
  auto& t = g.addVariable<VariableSE2>(0, se2(0.1, 0.1, 0.0));
  for (int k = 0; k < 20; ++k) {
    g.emplaceFactor<PointToLineFactor2D>(&t, Eigen::Vector2d(k * 0.1, 1.0),
                                         Eigen::Vector2d(k * 0.1, 1.0), Eigen::Vector2d(0, 1));
  }
  for (Algorithm alg : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt}) {
    t.setEstimate(se2(0.1, 0.1, 0.0));
    OptimizerOptions o;
    o.algorithm = alg;
    const OptimizeResult r = Optimizer(o).optimize(g);
    EXPECT_TRUE(t.estimate().matrix().allFinite());
    if (alg == Algorithm::kGaussNewton) {
      EXPECT_EQ(r.reason, StopReason::kSolverFailure);
      EXPECT_GE(r.singular_systems, 1);
    } else {
      // LM's damping regularises the system: it still reduces the observable error.
      EXPECT_LT(r.final_chi2, 1e-6);
    }
  }
}

TEST(Optimizer, RobustKernelDownweightsOutliers) {
  // Max position error after optimising a noise-free loop plus one wrong loop closure.
  auto run = [](const char* kernel) {
    Loop2D loop(30, 0.0, 9);
    loop.graph.emplaceFactor<BetweenFactorSE2>(&loop.graph.get<VariableSE2>(0),
                                               &loop.graph.get<VariableSE2>(15), se2(3, 3, 1.0),
                                               Eigen::Vector3d(10, 10, 100).asDiagonal());
    if (kernel) {
      std::shared_ptr<const RobustKernel> k = makeRobustKernel(kernel, 1.0);
      for (const auto& f : loop.graph.factors()) f->setRobustKernel(k);
    }
    OptimizerOptions o;
    o.max_iterations = 200;
    Optimizer(o).optimize(loop.graph);
    double max_err = 0.0;
    for (int i = 0; i < 30; ++i) {
      max_err = std::max(max_err, (loop.graph.get<VariableSE2>(i).estimate().translation() -
                                   loop.truth[i].translation())
                                      .norm());
    }
    return max_err;
  };
  const double plain = run(nullptr);
  EXPECT_GT(plain, 1.0);
  for (const char* k : {"sdk.Cauchy", "sdk.DCS"}) {
    const double err = run(k);
    EXPECT_LT(err, 0.2 * plain) << k << " plain " << plain;
  }
  // DCS stops the outlier's pull almost entirely.
  EXPECT_LT(run("sdk.DCS"), 0.05);
}

TEST(Optimizer, StereoBundleAdjustmentOfLandmarks) {
  // Two fixed cameras, landmarks start displaced; stereo factors triangulate them.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  PinholeCamera cam{500, 500, 320, 240, 0.2};
  FactorGraph g;
  auto& c0 = g.addVariable<VariableSE3>(0, SE3::Identity());
  auto& c1 = g.addVariable<VariableSE3>(
      1, se3(Eigen::Vector3d(0.5, 0, 0.2), Eigen::Quaterniond::Identity()));
  c0.setFixed(true);
  c1.setFixed(true);
  std::vector<Eigen::Vector3d> truth;
  for (int k = 0; k < 30; ++k) {
    truth.emplace_back(u(rng), u(rng), 6.0 + u(rng));
    auto& p =
        g.addVariable<VariablePoint3>(100 + k, truth.back() + Eigen::Vector3d(0.3, -0.2, 0.5));
    for (VariableSE3* c : {&c0, &c1}) {
      const Eigen::Vector3d pc = c->estimate().inverse() * truth.back();
      const Eigen::Vector3d z(cam.fx * pc.x() / pc.z() + cam.cx, cam.fy * pc.y() / pc.z() + cam.cy,
                              cam.fx * (pc.x() - cam.baseline) / pc.z() + cam.cx);
      g.emplaceFactor<StereoFactor>(c, &p, z, cam);
    }
  }
  const OptimizeResult r = Optimizer().optimize(g);
  EXPECT_TRUE(r.ok()) << toString(r.reason);
  EXPECT_LT(r.final_chi2, 1e-12);
  for (int k = 0; k < 30; ++k) {
    EXPECT_LT((g.get<VariablePoint3>(100 + k).estimate() - truth[k]).norm(), 1e-6);
  }
}

TEST(Optimizer, PointToPlaneAlignmentIn3D) {
  const SE3 truth = se3((Vector6d() << 0.2, -0.1, 0.3, 0.05, -0.1, 0.2).finished());
  FactorGraph g;
  auto& t = g.addVariable<VariableSE3>(0, SE3::Identity());
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const Eigen::Vector3d normals[6] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                      {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
  for (int k = 0; k < 300; ++k) {
    const Eigen::Vector3d& n = normals[k % 6];
    Eigen::Vector3d q(u(rng), u(rng), u(rng));
    q -= n * n.dot(q);
    q -= 4.0 * n;  // on the plane n.x = -4
    g.emplaceFactor<PointToPlaneFactor3D>(&t, truth.inverse() * q, q, n);
  }
  const OptimizeResult r = Optimizer().optimize(g);
  EXPECT_TRUE(r.ok());
  EXPECT_LT((toVector(t.estimate()) - toVector(truth)).norm(), 1e-8);
}

TEST(Optimizer, NothingToOptimize) {
  FactorGraph g;
  auto& a = g.addVariable<VariableSE2>(0, SE2::Identity());
  a.setFixed(true);
  g.emplaceFactor<PriorFactorSE2>(&a, se2(1, 0, 0));
  const OptimizeResult r = Optimizer().optimize(g);
  EXPECT_EQ(r.reason, StopReason::kNothingToOptimize);
  EXPECT_NEAR(r.final_chi2, 1.0, 1e-12);
}

TEST(Optimizer, EachDisconnectedComponentGetsItsGauge) {
  // Two separate loops in one graph: each needs its own anchor or H is singular.
  FactorGraph g;
  Loop2D a(12, 0.05, 21), b(9, 0.05, 22);
  for (Loop2D* loop : {&a, &b}) {
    const int64_t base = loop == &a ? 0 : 100;
    for (Variable* v : loop->graph.variables()) {
      g.addVariable<VariableSE2>(base + v->id(), static_cast<VariableSE2*>(v)->estimate());
    }
    for (const auto& f : loop->graph.factors()) {
      const auto& e = static_cast<const BetweenFactorSE2&>(*f);
      g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(base + e.variable(0)->id()),
                                        &g.get<VariableSE2>(base + e.variable(1)->id()),
                                        e.measurement(), e.information());
    }
  }
  OptimizerOptions o;
  o.dense_threshold = 0;
  const OptimizeResult r = Optimizer(o).optimize(g);
  EXPECT_TRUE(r.ok()) << toString(r.reason);
  EXPECT_EQ(r.system_size, (11 + 8) * 3);
  EXPECT_EQ(r.singular_systems, 0);
  EXPECT_EQ(g.get<VariableSE2>(100).estimate().matrix(),
            b.graph.get<VariableSE2>(0).estimate().matrix());
}

TEST(Optimizer, SingularSparseSystemGnFailsCleanlyLmRecovers) {
  // Pose 40 hangs on a factor with zero information: its block of H is zero.
  for (Algorithm alg : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt}) {
    Loop2D loop(40, 0.05, 13);
    auto& extra = loop.graph.addVariable<VariableSE2>(40, se2(1, 2, 0.3));
    loop.graph.emplaceFactor<BetweenFactorSE2>(&loop.graph.get<VariableSE2>(5), &extra,
                                               se2(1, 0, 0), Eigen::Matrix3d::Zero());
    OptimizerOptions o;
    o.algorithm = alg;
    o.dense_threshold = 0;
    const OptimizeResult r = Optimizer(o).optimize(loop.graph);
    for (Variable* v : loop.graph.variables()) {
      EXPECT_TRUE(static_cast<VariableSE2*>(v)->estimate().matrix().allFinite());
    }
    if (alg == Algorithm::kGaussNewton) {
      EXPECT_GE(r.singular_systems, 1);
      EXPECT_EQ(r.reason, StopReason::kSolverFailure);
      EXPECT_EQ(r.final_chi2, r.initial_chi2);  // the failed step was not applied
    } else {
      // The damping keeps the system positive definite; the free pose simply does not move.
      EXPECT_TRUE(r.ok()) << toString(r.reason);
      EXPECT_LT(r.final_chi2, 1e-3 * r.initial_chi2);
      EXPECT_LT((toVector(extra.estimate()) - Eigen::Vector3d(1, 2, 0.3)).norm(), 1e-6);
    }
  }
}

TEST(Optimizer, BlockAndCholmodFactorisationsAgreeIn3D) {
  // A noisy 3D ring with chords: 6x6 blocks go through the block Cholesky (auto, block) and
  // CHOLMOD (supernodal, simplicial); all must reach the same minimum.
  auto build = [](FactorGraph& g) {
    std::mt19937 rng(21);
    std::normal_distribution<double> nd(0.0, 1.0);
    const int n = 30;
    std::vector<SE3> truth;
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * M_PI * k / n;
      Vector6d v;
      v << 4.0 * std::cos(a), 4.0 * std::sin(a), 0.3 * std::sin(3 * a), 0.1 * std::sin(a), 0.0, a;
      truth.push_back(se3(v));
      Vector6d noise;
      for (int i = 0; i < 6; ++i) noise[i] = (i < 3 ? 0.2 : 0.05) * nd(rng);
      g.addVariable<VariableSE3>(k, k == 0 ? truth[0] : SE3(truth[k] * se3(noise)));
    }
    auto link = [&](int i, int j) {
      Vector6d noise;
      for (int d = 0; d < 6; ++d) noise[d] = 0.01 * nd(rng);
      g.emplaceFactor<BetweenFactorSE3>(&g.get<VariableSE3>(i), &g.get<VariableSE3>(j),
                                        SE3(truth[i].inverse() * truth[j] * se3(noise)));
    };
    for (int k = 0; k < n; ++k) link(k, (k + 1) % n);
    for (int k = 0; k < n; k += 5) link(k, (k + n / 2) % n);
  };
  std::vector<double> finals;
  for (Factorization f : {Factorization::kAuto, Factorization::kBlock, Factorization::kSupernodal,
                          Factorization::kSimplicial}) {
    FactorGraph g;
    build(g);
    OptimizerOptions o;
    o.algorithm = Algorithm::kGaussNewton;
    o.dense_threshold = 0;
    o.factorization = f;
    const OptimizeResult r = Optimizer(o).optimize(g);
    EXPECT_TRUE(r.ok()) << toString(r.reason);
    EXPECT_EQ(r.system_size, 29 * 6);
    EXPECT_LT(r.final_chi2, 1e-2 * r.initial_chi2);
    finals.push_back(r.final_chi2);
  }
  for (double c : finals) EXPECT_NEAR(c, finals.front(), 1e-9 * finals.front());
}

namespace {

// An SE2 pose graph on n poses with the given edges (i, j), measured noise-free from random
// true poses; the estimates start 0.05 off the truth.
void buildPoseGraph(FactorGraph& g, int n, const std::vector<std::pair<int, int>>& edges,
                    unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  std::vector<SE2> truth;
  for (int k = 0; k < n; ++k) truth.push_back(se2(30.0 * nd(rng), 30.0 * nd(rng), nd(rng)));
  for (int k = 0; k < n; ++k) {
    g.addVariable<VariableSE2>(
        k, k == 0 ? truth[0] : SE2(truth[k] * se2(0.05 * nd(rng), 0.05 * nd(rng), 0.05 * nd(rng))));
  }
  for (const auto& [i, j] : edges) {
    g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(i), &g.get<VariableSE2>(j),
                                      SE2(truth[i].inverse() * truth[j]),
                                      Eigen::Vector3d(10, 10, 100).asDiagonal());
  }
}

OptimizeResult optimizeWith(FactorGraph& g, Factorization f) {
  OptimizerOptions o;
  o.algorithm = Algorithm::kGaussNewton;
  o.dense_threshold = 0;
  o.factorization = f;
  return Optimizer(o).optimize(g);
}

}  // namespace

TEST(Optimizer, AutoKeepsTheBlockPathOnSparseFillAndLeavesItOnDenseFill) {
  const int n = 900;
  std::vector<std::pair<int, int>> chain, grid, dense;
  for (int k = 0; k + 1 < n; ++k) chain.emplace_back(k, k + 1);
  // A 30 x 30 grid: planar, nested dissection keeps L's columns short.
  for (int r = 0; r < 30; ++r) {
    for (int c = 0; c < 30; ++c) {
      if (c + 1 < 30) grid.emplace_back(30 * r + c, 30 * r + c + 1);
      if (r + 1 < 30) grid.emplace_back(30 * r + c, 30 * (r + 1) + c);
    }
  }
  // The chain plus loops from every pose to three random others: like one place mapped over
  // and over, no small separator exists and L fills in densely.
  dense = chain;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int k = 0; k < n; ++k) {
    for (int e = 0; e < 3; ++e) {
      const int j = pick(rng);
      if (j != k) dense.emplace_back(k, j);
    }
  }
  for (const auto* edges : {&chain, &grid}) {
    FactorGraph g;
    buildPoseGraph(g, n, *edges, 1);
    const OptimizeResult r = optimizeWith(g, Factorization::kAuto);
    EXPECT_TRUE(r.ok()) << toString(r.reason);
    EXPECT_EQ(r.factorization, Factorization::kBlock) << toString(r.factorization);
  }
  std::vector<double> finals;
  for (Factorization f : {Factorization::kAuto, Factorization::kBlock}) {
    FactorGraph g;
    buildPoseGraph(g, n, dense, 1);
    Optimizer optimizer;
    optimizer.options().algorithm = Algorithm::kGaussNewton;
    optimizer.options().dense_threshold = 0;
    optimizer.options().factorization = f;
    const OptimizeResult r = optimizer.optimize(g);
    EXPECT_TRUE(r.ok()) << toString(r.reason);
    EXPECT_LT(r.final_chi2, 1e-6 * r.initial_chi2);
    // On the reference BLAS the block kernels win at any fill (docs/benchmarks.md, History).
    const Factorization expected = f == Factorization::kAuto && hasOptimizedBlas()
                                       ? Factorization::kSupernodal
                                       : Factorization::kBlock;
    EXPECT_EQ(r.factorization, expected) << toString(r.factorization);
    finals.push_back(r.final_chi2);
    // The decision is kept for the unchanged structure.
    EXPECT_EQ(optimizer.optimize(g).factorization, expected);
  }
  EXPECT_NEAR(finals[0], finals[1], 1e-9 + 1e-6 * finals[1]);
  // An explicit choice is obeyed whatever the fill; the dense path reports none.
  FactorGraph g;
  buildPoseGraph(g, n, chain, 2);
  EXPECT_EQ(optimizeWith(g, Factorization::kSimplicial).factorization, Factorization::kSimplicial);
  FactorGraph small;
  buildPoseGraph(small, 5, {{0, 1}, {1, 2}, {2, 3}, {3, 4}}, 3);
  const OptimizeResult rs = Optimizer().optimize(small);
  EXPECT_TRUE(rs.dense);
  EXPECT_EQ(rs.factorization, Factorization::kAuto);
}
