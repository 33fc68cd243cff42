#pragma once
// Figures a module reports about its run beyond its wall time (per-stage times, feature and
// landmark counts), collected into run.json by the host. A module opts in by also deriving from
// StatisticsSource; nothing else in the module interfaces changes.
#include <string>
#include <utility>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

class Configurable;

/// One named figure ("extraction_s", "keypoints_per_frame").
struct Statistic {
  std::string name;  ///< key in run.json, snake_case with its unit as suffix where it has one
  double value = 0;  ///< the figure
};

/// Implemented by modules that report figures of their own.
class StatisticsSource {
 public:
  virtual ~StatisticsSource();
  /// The module's figures over the run so far.
  virtual std::vector<Statistic> statistics() const = 0;
};

/// The figures of every StatisticsSource in the module tree under `root` (root first, then its
/// slots depth first), each with the module's instance name.
std::vector<std::pair<std::string, std::vector<Statistic>>> collectStatistics(
    const Configurable& root);

}  // namespace abi_v1
}  // namespace plugslam
