#include "plugslam/eval/stats.h"

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

ErrorStats computeErrorStats(const std::vector<double>& values) {
  if (values.empty()) throw InputError("cannot compute statistics of zero errors");
  ErrorStats s;
  s.count = values.size();
  const double n = static_cast<double>(values.size());
  double sum = 0.0, sum_sq = 0.0;
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  s.min = sorted.front();
  s.max = sorted.back();
  const std::size_t mid = sorted.size() / 2;
  s.median = sorted.size() % 2 == 1 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
  return s;
}

MeanStd computeMeanStd(const std::vector<double>& values) {
  if (values.empty()) throw InputError("cannot compute statistics of zero errors");
  MeanStd m;
  double sum = 0.0;
  for (double v : values) sum += v;
  m.mean = sum / static_cast<double>(values.size());
  if (values.size() > 1) {
    double var = 0.0;
    for (double v : values) var += (v - m.mean) * (v - m.mean);
    m.std = std::sqrt(var / static_cast<double>(values.size() - 1));
  }
  return m;
}

}  // namespace abi_v1
}  // namespace plugslam
