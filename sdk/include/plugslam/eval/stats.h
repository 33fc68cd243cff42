#pragma once
// Summary statistics of error samples, as trajectory-evaluation tools report them.
#include <cstddef>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

/// rmse, mean, median, std (population, as evo), min, max and count of a list of errors.
struct ErrorStats {
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  std::size_t count = 0;
};

/// Computes ErrorStats; throws InputError when values is empty.
ErrorStats computeErrorStats(const std::vector<double>& values);

/// Mean and sample standard deviation (n - 1, as the relation-metric tools report "mean ± std").
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
};

/// Computes MeanStd; std is 0 for a single value; throws InputError when values is empty.
MeanStd computeMeanStd(const std::vector<double>& values);

}  // namespace abi_v1
}  // namespace plugslam
