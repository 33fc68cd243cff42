#pragma once
// Figures a module reports about its run beyond its wall time (per-stage times, feature and
// landmark counts), collected into run.json by the host. A module opts in by also deriving from
// StatisticsSource; nothing else in the module interfaces changes.
#include <chrono>
#include <cstdint>
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

/// Adds the lifetime of a scope to a running total of seconds (a module's stage time).
class Stopwatch {
 public:
  /// Starts timing into `total_s`.
  explicit Stopwatch(double& total_s) : total_(total_s), start_(std::chrono::steady_clock::now()) {}
  ~Stopwatch() {
    total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

/// A per-frame figure: total / frames, 0 before the first frame.
inline double perFrame(std::uint64_t total, std::uint64_t frames) {
  return frames ? static_cast<double>(total) / static_cast<double>(frames) : 0.0;
}

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
