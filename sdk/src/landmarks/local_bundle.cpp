#include "plugslam/landmarks/local_bundle.h"

#include <spdlog/spdlog.h>

#include <memory>
#include <unordered_map>

#include "plugslam/landmarks/observation_factor.h"
#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/optimizer.h"
#include "plugslam/solver/robust_kernel.h"

namespace plugslam {
inline namespace abi_v1 {

BundleResult adjustBundle(std::vector<BundleFrame>& frames, LandmarkMap& map,
                          const BundleOptions& options) {
  BundleResult result;
  std::unordered_map<uint64_t, size_t> index;  // track id -> position in the map
  index.reserve(map.size());
  for (size_t j = 0; j < map.size(); ++j) index.emplace(map.ids[j], j);
  // A landmark seen by one frame only is fixed by that frame alone: it adds unknowns, no check.
  std::unordered_map<uint64_t, int> seen;
  for (const BundleFrame& f : frames)
    for (const BundleObservation& o : f.observations)
      if (index.count(o.landmark)) ++seen[o.landmark];

  FactorGraph graph;
  std::vector<VariableSE3*> poses;
  for (size_t k = 0; k < frames.size(); ++k) {
    VariableSE3& v = graph.addVariable<VariableSE3>(static_cast<int64_t>(k), frames[k].pose);
    v.setFixed(frames[k].fixed);
    poses.push_back(&v);
  }
  const int64_t first_point = static_cast<int64_t>(frames.size());
  std::unordered_map<uint64_t, VariablePoint3*> points;
  std::shared_ptr<const RobustKernel> kernel = makeRobustKernel("huber", options.kernel_scale);
  for (size_t k = 0; k < frames.size(); ++k)
    for (const BundleObservation& o : frames[k].observations) {
      const auto s = seen.find(o.landmark);
      if (s == seen.end() || s->second < 2) continue;
      VariablePoint3*& p = points[o.landmark];
      if (!p)
        p = &graph.addVariable<VariablePoint3>(first_point + static_cast<int64_t>(points.size()),
                                               map.positions[index.at(o.landmark)]);
      auto& f = graph.emplaceFactor<LandmarkObservationFactor>(poses[k], p, o.measured,
                                                               frames[k].camera, frames[k].mount);
      f.setInformation(o.information.asDiagonal());
      f.setRobustKernel(kernel);
      ++result.observations;
    }
  result.frames = static_cast<int>(frames.size());
  result.landmarks = static_cast<int>(points.size());
  if (points.empty()) return result;
  OptimizerOptions oo;
  oo.max_iterations = options.iterations;
  oo.gauge = GaugeMode::kNone;  // the fixed frames hold the map's frame
  Optimizer optimizer(oo);
  const OptimizeResult r = optimizer.optimize(graph);
  result.chi2_before = r.initial_chi2;
  result.chi2_after = r.final_chi2;
  spdlog::trace("bundle: {} frames, {} landmarks, {} observations: chi2 {:.1f} -> {:.1f} in {} "
                "iterations, {:.1f} ms ({:.1f} ms setup), {} unknowns",
                result.frames, result.landmarks, result.observations, r.initial_chi2,
                r.final_chi2, r.iterations, 1e3 * r.time_total, 1e3 * r.time_setup,
                r.system_size);
  if (!(r.final_chi2 < r.initial_chi2)) return result;
  for (const auto& [id, p] : points) map.positions[index.at(id)] = p->estimate();
  for (size_t k = 0; k < frames.size(); ++k) frames[k].pose = poses[k]->estimate();
  map.touch();
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
