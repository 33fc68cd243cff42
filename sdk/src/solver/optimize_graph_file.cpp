#include "plugslam/solver/optimize_graph_file.h"

#include <chrono>
#include <cstdio>
#include <memory>

#include "plugslam/errors.h"
#include "plugslam/solver/initialization.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}
}  // namespace

InitMethod parseInitMethod(const std::string& name) {
  if (name == "file") return InitMethod::kFile;
  if (name == "odometry") return InitMethod::kOdometry;
  if (name == "chordal") return InitMethod::kChordal;
  if (name == "best") return InitMethod::kBest;
  throw InputError("unknown initialisation '" + name +
                   "'; expected file, odometry, chordal or best");
}

Algorithm parseAlgorithm(const std::string& name) {
  if (name == "gn") return Algorithm::kGaussNewton;
  if (name == "lm") return Algorithm::kLevenbergMarquardt;
  throw InputError("unknown solver '" + name + "'; expected gn or lm");
}

OptimizeReport optimizeGraphFile(const OptimizeOptions& options) {
  if (options.max_iterations < 0) throw InputError("iterations must be >= 0");
  OptimizeReport report;
  FactorGraph graph;
  auto t0 = Clock::now();
  ReadGraphOptions read_options;
  read_options.project_information = options.project_information;
  report.file = readGraphFile(options.input, graph, read_options);
  report.time_read = since(t0);
  report.poses = graph.numVariables();
  report.edges = graph.numFactors();
  if (report.file.non_pd_information > 0 && !options.project_information) {
    throw InputError(options.input + ": " + std::to_string(report.file.non_pd_information) +
                     " of " + std::to_string(report.file.edges) +
                     " edges have an information matrix that is not positive definite; "
                     "optimise with information projection enabled to project each to the "
                     "nearest positive definite matrix");
  }
  const std::vector<Eigen::Vector2d> weights = seSyncWeights(graph);
  if (options.se_sync_weights) applySeSyncWeights(graph);
  if (!options.robust_kernel.empty()) {
    std::shared_ptr<const RobustKernel> kernel =
        makeRobustKernel(options.robust_kernel, options.robust_scale);
    for (const auto& f : graph.factors()) f->setRobustKernel(kernel);
  }

  OptimizerOptions oo;
  oo.algorithm = options.algorithm;
  oo.max_iterations = options.max_iterations;
  oo.factorization = options.factorization;
  Optimizer optimizer(oo);
  if (options.on_iteration) optimizer.setIterationCallback(options.on_iteration);

  // kBest: optimise from the file's poses (odometry for edge-only files) first, keep those
  // estimates, then from chordal; the lower final cost wins.
  const bool best_of = options.init == InitMethod::kBest;
  std::vector<SE2> keep2;
  std::vector<SE3> keep3;
  OptimizeResult first;
  if (best_of) {
    t0 = Clock::now();
    if (!report.file.has_vertices) initializeSpanningTree(graph);
    report.time_init += since(t0);
    first = optimizer.optimize(graph);
    report.time_optimize += first.time_total;
    for (Variable* v : graph.variables()) {
      if (auto* p2 = dynamic_cast<VariableSE2*>(v)) keep2.push_back(p2->estimate());
      if (auto* p3 = dynamic_cast<VariableSE3*>(v)) keep3.push_back(p3->estimate());
    }
  }

  t0 = Clock::now();
  InitMethod init = best_of ? InitMethod::kChordal : options.init;
  if (init == InitMethod::kFile && !report.file.has_vertices) init = InitMethod::kOdometry;
  if (init == InitMethod::kOdometry) initializeSpanningTree(graph);
  if (init == InitMethod::kChordal) initializeChordal(graph);
  report.time_init += since(t0);

  report.result = optimizer.optimize(graph);
  report.time_optimize += report.result.time_total;
  if (best_of && first.final_chi2 < report.result.final_chi2) {
    size_t k2 = 0, k3 = 0;
    for (Variable* v : graph.variables()) {
      if (auto* p2 = dynamic_cast<VariableSE2*>(v)) p2->setEstimate(keep2[k2++]);
      if (auto* p3 = dynamic_cast<VariableSE3*>(v)) p3->setEstimate(keep3[k3++]);
    }
    report.result = first;
  }
  report.initial_chi2 = report.result.initial_chi2;
  report.final_chi2 = report.result.final_chi2;
  report.iterations = report.result.iterations;
  report.reason = report.result.reason;
  report.se_sync_objective = seSyncObjective(graph, weights);

  if (!options.output.empty()) {
    t0 = Clock::now();
    writeGraphFile(options.output, graph);
    report.time_write = since(t0);
  }
  return report;
}

std::string toJson(const OptimizeReport& r) {
  char buf[1024];
  std::snprintf(
      buf, sizeof(buf),
      "{\"poses\": %zu, \"edges\": %zu, \"dimension\": %d, \"non_pd_information\": %zu, "
      "\"initial_chi2\": %.17g, \"final_chi2\": %.17g, \"se_sync_objective\": %.17g, "
      "\"iterations\": %d, \"stop_reason\": \"%s\", \"factorization_used\": \"%s\", "
      "\"time_read\": %.6f, \"time_init\": %.6f, \"time_optimize\": %.6f, \"time_write\": %.6f}",
      r.poses, r.edges, r.file.dimension, r.file.non_pd_information, r.initial_chi2, r.final_chi2,
      r.se_sync_objective, r.iterations, toString(r.reason),
      r.result.dense ? "dense" : toString(r.result.factorization), r.time_read, r.time_init,
      r.time_optimize, r.time_write);
  return buf;
}

}  // namespace abi_v1
}  // namespace plugslam
