#pragma once
// The whole `plugslam optimize` job as one call: read a pose-graph file, initialise, optimise,
// write, report. The CLI command is a thin shell around optimizeGraphFile().
#include <functional>
#include <string>

#include "plugslam/solver/graph_io.h"
#include "plugslam/solver/optimizer.h"

namespace plugslam {
inline namespace abi_v1 {

/// Where the optimisation starts.
enum class InitMethod {
  kFile,      ///< the file's vertex estimates (edge-only files fall back to kOdometry)
  kOdometry,  ///< compose measurements along a spanning tree
  kChordal,   ///< chordal relaxation of rotations, then translations
  kBest,      ///< optimise from kFile and from kChordal, keep the lower cost (twice the time)
};

/// Parses "file", "odometry", "chordal" or "best"; throws InputError otherwise.
InitMethod parseInitMethod(const std::string& name);
/// Parses "gn" or "lm"; throws InputError otherwise.
Algorithm parseAlgorithm(const std::string& name);

/// Settings of optimizeGraphFile.
struct OptimizeOptions {
  std::string input;                              ///< g2o or TORO file
  std::string output;                             ///< g2o file to write; empty: do not write
  Algorithm algorithm = Algorithm::kGaussNewton;  ///< GN or LM
  int max_iterations = 100;                       ///< iteration budget
  InitMethod init = InitMethod::kChordal;         ///< starting point
  std::string robust_kernel;                      ///< empty: none; else a makeRobustKernel name
  double robust_scale = 1.0;                      ///< kernel scale
  bool project_information = false;  ///< optimise graphs with non-PD information by projecting
  Factorization factorization = Factorization::kAuto;  ///< CHOLMOD factorisation kind
  bool se_sync_weights = false;  ///< minimise the SE-Sync objective (applySeSyncWeights)
  std::function<void(const IterationStats&)> on_iteration;  ///< per-iteration callback
};

/// What optimizeGraphFile did.
struct OptimizeReport {
  GraphFileInfo file;              ///< what the file held
  size_t poses = 0;                ///< variables
  size_t edges = 0;                ///< factors
  double initial_chi2 = 0.0;       ///< cost after initialisation (g2o's chi2 without a kernel)
  double final_chi2 = 0.0;         ///< cost at the end
  double se_sync_objective = 0.0;  ///< SE-Sync objective of the final estimate
  int iterations = 0;              ///< optimizer iterations
  StopReason reason = StopReason::kNothingToOptimize;  ///< why the optimizer stopped
  double time_read = 0.0;                              ///< seconds reading
  double time_init = 0.0;                              ///< seconds initialising
  double time_optimize = 0.0;                          ///< seconds in the optimizer
  double time_write = 0.0;                             ///< seconds writing
  OptimizeResult result;  ///< the optimizer's own result, with per-iteration stats
};

/// Reads, initialises, optimises and writes. Throws ParseError/InputError for bad input,
/// including a graph with non-positive-definite information unless project_information is set.
OptimizeReport optimizeGraphFile(const OptimizeOptions& options);

/// A JSON object summarising the report (initial and final chi2, iterations, times, ...).
std::string toJson(const OptimizeReport& report);

}  // namespace abi_v1
}  // namespace plugslam
