#include "modules/graph/global_optimizer.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <memory>

#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/optimizer.h"
#include "plugslam/solver/pose_factors.h"
#include "plugslam/solver/robust_kernel.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

namespace {

// Information of the weak prior tying a later component's first map to map 0 where the estimate
// has it; it only keeps the system non-singular until a loop joins the components.
constexpr double kAnchorInformation = 1e-8;

// The solver's variable and factor types of each pose space.
template <class S>
struct GraphTypes;
template <>
struct GraphTypes<Space2D> {
  using Variable = VariableSE2;
  using Between = BetweenFactorSE2;
  using Information = Eigen::Matrix3d;
};
template <>
struct GraphTypes<Space3D> {
  using Variable = VariableSE3;
  using Between = BetweenFactorSE3;
  using Information = Eigen::Matrix<double, 6, 6>;
};

// Fills `graph` with the problem's variables (the first fixed), between factors and anchors.
template <class S>
void buildGraph(const typename GlobalOptimizer<S>::Problem& problem, FactorGraph& graph) {
  using T = GraphTypes<S>;
  std::shared_ptr<const RobustKernel> kernel;
  const OptimizerSettings& settings = problem.settings;
  if (settings.loop_kernel != "none")
    kernel = makeRobustKernel(settings.loop_kernel, settings.loop_kernel_scale);
  std::vector<typename T::Variable*> vars;
  vars.reserve(problem.before.size());
  for (size_t i = 0; i < problem.before.size(); ++i)
    vars.push_back(
        &graph.addVariable<typename T::Variable>(static_cast<int64_t>(i), problem.before[i]));
  if (!vars.empty()) vars[0]->setFixed(true);
  for (const GraphEdge& e : problem.edges) {
    auto& f = graph.emplaceFactor<typename T::Between>(vars[e.from], vars[e.to],
                                                       S::from3D(e.relative),
                                                       typename T::Information(
                                                           betweenFactorInformation(e, S::kDim)));
    if (e.loop && kernel) f.setRobustKernel(kernel);
  }
  for (size_t a : problem.anchors) {
    const typename S::Matrix info = S::Matrix::Identity() * kAnchorInformation;
    graph.emplaceFactor<typename T::Between>(
        vars[0], vars[a], S::normalized(problem.before[0].inverse() * problem.before[a]),
        typename T::Information(info));
  }
}

}  // namespace

template <class S>
typename GlobalOptimizer<S>::Problem GlobalOptimizer<S>::snapshot(
    const PoseGraph& graph, const OptimizerSettings& settings, std::vector<GraphEdge> edges) {
  Problem problem;
  problem.settings = settings;
  const auto& maps = graph.maps();
  for (size_t i = 1; i < maps.size(); ++i)
    if (maps[i]->previous < 0) problem.anchors.push_back(i);
  problem.edges = std::move(edges);
  problem.before.reserve(maps.size());
  for (const auto& m : maps) problem.before.push_back(S::from3D(m->origin));
  return problem;
}

template <class S>
Solution GlobalOptimizer<S>::solve(const Problem& problem) {
  const auto start = std::chrono::steady_clock::now();
  OptimizerOptions options;
  options.algorithm = problem.settings.solver == "lm" ? Algorithm::kLevenbergMarquardt
                                                      : Algorithm::kGaussNewton;
  options.max_iterations = problem.settings.iterations;
  auto graph = std::make_unique<FactorGraph>();
  buildGraph<S>(problem, *graph);
  OptimizeResult r = Optimizer(options).optimize(*graph);
  if (options.algorithm == Algorithm::kGaussNewton && r.final_chi2 > r.initial_chi2) {
    // Gauss-Newton does not guarantee descent: far from the solution (a large correction,
    // loose tracking-failure edges) it can diverge and throw the map away. Levenberg-Marquardt
    // from the same start never increases the cost.
    spdlog::debug("global optimization: Gauss-Newton raised chi2 from {:.6g} to {:.6g}; "
                  "Levenberg-Marquardt instead",
                  r.initial_chi2, r.final_chi2);
    options.algorithm = Algorithm::kLevenbergMarquardt;
    graph = std::make_unique<FactorGraph>();
    buildGraph<S>(problem, *graph);
    r = Optimizer(options).optimize(*graph);
  }
  Solution solution;
  solution.nodes = problem.before.size();
  solution.edges = problem.edges;
  solution.ok = r.ok();
  solution.chi2 = r.final_chi2;
  using Variable = typename GraphTypes<S>::Variable;
  solution.before.reserve(solution.nodes);
  solution.after.reserve(solution.nodes);
  for (size_t i = 0; i < solution.nodes; ++i) {
    solution.before.push_back(S::to3D(problem.before[i]));
    solution.after.push_back(S::to3D(graph->get<Variable>(static_cast<int64_t>(i)).estimate()));
  }
  solution.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return solution;
}

template <class S>
void GlobalOptimizer<S>::start(Problem problem) {
  auto shared = std::make_shared<Problem>(std::move(problem));
  running_ = std::async(std::launch::async, [shared] { return solve(*shared); });
}

template <class S>
bool GlobalOptimizer<S>::ready() const {
  return running_.valid() &&
         running_.wait_for(std::chrono::seconds(0)) == std::future_status::ready;
}

template <class S>
GlobalOptimizer<S>::~GlobalOptimizer() {
  if (running_.valid()) running_.wait();
}

template class GlobalOptimizer<Space2D>;
template class GlobalOptimizer<Space3D>;

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
