// The aligner's per-frame solve (one SE2 pose, hundreds of factors) must not allocate per
// iteration: counts heap allocations inside Optimizer::optimize() with a replaced operator new.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "plugslam/solver/optimizer.h"
#include "plugslam/solver/registration_factors.h"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The replacement pair is malloc/free by design; GCC cannot tell and warns.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

using namespace plugslam;

TEST(OptimizerAllocations, DensePathAllocatesIndependentlyOfIterations) {
  FactorGraph g;
  auto& t = g.addVariable<VariableSE2>(0, SE2::Identity());
  const SE2 truth = se2(0.2, -0.1, 0.1);
  for (int k = 0; k < 400; ++k) {
    const double a = 0.0157 * k;
    const Eigen::Vector2d q(4.0 * std::cos(a) + (k % 2), 3.0 * std::sin(3 * a));
    const Eigen::Vector2d n(std::cos(a + k), std::sin(a + k));
    g.emplaceFactor<PointToLineFactor2D>(&t, truth.inverse() * q, q, n);
  }
  OptimizerOptions o;
  o.relative_decrease = 0.0;  // run all iterations
  o.step_norm = 0.0;
  o.absolute_chi2 = 0.0;
  Optimizer opt(o);
  opt.optimize(g);  // warm-up: buffers sized here
  long per_call[2];
  int iterations[2];
  for (int run = 0; run < 2; ++run) {
    opt.options().max_iterations = run == 0 ? 3 : 30;
    t.setEstimate(SE2::Identity());
    const long before = g_allocations.load();
    const OptimizeResult r = opt.optimize(g);
    per_call[run] = g_allocations.load() - before;
    iterations[run] = r.iterations;
  }
  EXPECT_GT(iterations[1], iterations[0]);
  EXPECT_EQ(per_call[0], per_call[1]) << "allocations grow with the iteration count";
  EXPECT_LE(per_call[1], 1) << "allocations per optimize() call (the stats vector)";
}
