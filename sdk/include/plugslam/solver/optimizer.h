#pragma once
// Gauss-Newton and Levenberg-Marquardt over a FactorGraph. The normal equations are assembled
// block-sparse straight into the factorisation's storage through scatter slots computed once per
// structure; the symbolic factorisation (block AMD ordering) is reused across iterations and
// across optimize() calls on an unchanged structure. When every variable has the same dimension
// (pose graphs), an up-looking block Cholesky with fixed-size kernels replaces CHOLMOD. Small
// systems use a dense Eigen LDLT whose buffers are kept between calls, so the aligner's per-frame
// solve does not allocate per iteration.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plugslam/solver/factor_graph.h"

namespace plugslam {
inline namespace abi_v1 {

/// The iteration scheme.
enum class Algorithm { kGaussNewton, kLevenbergMarquardt };

/// How the optimizer treats the gauge freedom of relative-only problems.
enum class GaugeMode {
  kAuto,  ///< per connected component without a fixed variable or unary factor, fix its first
  kNone,  ///< never fix anything implicitly
};

/// CHOLMOD's factorisation kind for the sparse path.
enum class Factorization {
  kSupernodal,  ///< supernodal LL' (BLAS-3 on dense supernodes)
  kSimplicial,  ///< simplicial LDL' (no BLAS; often faster for small blocks and plain BLAS)
  kAuto,        ///< block LL' when every variable has the same dimension (supernodal instead
                ///< when L fills in densely and the BLAS is optimised); else CHOLMOD's choice
  kBlock,       ///< plugslam's block LL' (equal-size variables; otherwise CHOLMOD's choice)
};

/// "supernodal", "simplicial", "auto" or "block".
const char* toString(Factorization f);

/// Whether CHOLMOD runs on an optimised BLAS (OpenBLAS, MKL or BLIS loaded in the process):
/// only then does kAuto trade the block kernels for supernodal on densely filling graphs.
bool hasOptimizedBlas();

/// Why an optimisation stopped.
enum class StopReason {
  kConverged,          ///< relative cost decrease or step norm below threshold
  kMaxIterations,      ///< iteration budget used
  kNoProgress,         ///< LM could not find a decreasing step
  kSolverFailure,      ///< GN: the system was singular/indefinite, the step was rejected
  kNothingToOptimize,  ///< no free variable or no factor
};

/// Human-readable name of a stop reason.
const char* toString(StopReason r);

/// Optimizer settings.
struct OptimizerOptions {
  Algorithm algorithm = Algorithm::kLevenbergMarquardt;  ///< GN or LM
  int max_iterations = 100;            ///< outer iterations (each one linearisation)
  double relative_decrease = 1e-6;     ///< stop when (chi2_old - chi2_new) / chi2_old is below
  double absolute_chi2 = 1e-12;        ///< stop when the cost falls below
  double step_norm = 1e-9;             ///< stop when max |dx| is below
  double lm_initial_tau = 1e-8;        ///< LM: lambda0 = tau * max diag(H)
  int lm_max_rejections = 10;          ///< LM: consecutive rejected steps before giving up
  int dense_threshold = 60;            ///< systems of at most this many scalars use dense LDLT
  GaugeMode gauge = GaugeMode::kAuto;  ///< implicit gauge fixing
  Factorization factorization = Factorization::kAuto;  ///< sparse path factorisation
  bool verbose = false;                                ///< log each iteration with spdlog (info)
};

/// Statistics of one outer iteration.
struct IterationStats {
  int iteration = 0;            ///< 0-based
  double chi2 = 0.0;            ///< robust cost after the iteration
  double chi2_before = 0.0;     ///< robust cost before it
  double step_norm = 0.0;       ///< max |dx| of the accepted step (0 if none)
  double lambda = 0.0;          ///< LM damping used for the accepted step (0 for GN)
  int rejected_steps = 0;       ///< LM: steps rejected in this iteration
  bool accepted = true;         ///< whether the estimate changed
  double time_linearize = 0.0;  ///< seconds assembling H and b
  double time_solve = 0.0;      ///< seconds in the factorisation and solves
  double time_update = 0.0;     ///< seconds applying steps and evaluating the cost
};

/// Outcome of optimize().
struct OptimizeResult {
  StopReason reason = StopReason::kNothingToOptimize;  ///< why it stopped
  int iterations = 0;                                  ///< outer iterations run
  double initial_chi2 = 0.0;                           ///< robust cost at the start
  double final_chi2 = 0.0;                             ///< robust cost at the end
  double time_total = 0.0;                             ///< seconds in optimize()
  double time_setup = 0.0;            ///< seconds building the structure and symbolic factorisation
  int system_size = 0;                ///< scalar unknowns
  bool dense = false;                 ///< dense path used
  int singular_systems = 0;           ///< factorisations that failed (indefinite or singular)
  /// The sparse factorisation that solved the system: kBlock, kSupernodal or kSimplicial; kAuto
  /// when none did (the dense path, or nothing to optimise). Added in ABI 1.2 in what was the
  /// padding before `stats`: size and layout are those of 1.1, so 1.1 plugins still call optimize.
  Factorization factorization = Factorization::kAuto;
  std::vector<IterationStats> stats;  ///< one entry per iteration
  /// True when the run stopped without a failure (converged or out of iterations).
  bool ok() const {
    return reason == StopReason::kConverged || reason == StopReason::kMaxIterations;
  }
};

/// GN/LM optimizer. Keep one instance per problem stream: it caches the structure, the
/// symbolic factorisation and the dense buffers between calls.
class Optimizer {
 public:
  /// An optimizer with the given settings.
  explicit Optimizer(const OptimizerOptions& options = {});
  ~Optimizer();
  Optimizer(const Optimizer&) = delete;
  Optimizer& operator=(const Optimizer&) = delete;

  /// Settings (mutable between calls).
  OptimizerOptions& options() { return options_; }
  /// Called after every iteration.
  void setIterationCallback(std::function<void(const IterationStats&)> callback) {
    callback_ = std::move(callback);
  }
  /// Optimises the graph's free variables in place. Never leaves NaN in an estimate.
  OptimizeResult optimize(FactorGraph& graph);

 private:
  struct Impl;
  OptimizerOptions options_;
  std::function<void(const IterationStats&)> callback_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace abi_v1
}  // namespace plugslam
