#include "plugslam/eval/association.h"

#include <cmath>

#include "eval/text_file.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

std::vector<PosePair> associate(const Trajectory& reference, const Trajectory& estimate,
                                const AssociationOptions& options) {
  if (reference.empty()) throw InputError("cannot associate: the reference trajectory is empty");
  if (estimate.empty()) throw InputError("cannot associate: the estimate trajectory is empty");
  if (!(options.max_time_diff >= 0.0) || !std::isfinite(options.time_offset)) {
    throw InputError("association needs max_time_diff >= 0 and a finite time_offset");
  }
  std::vector<PosePair> pairs;
  std::vector<double> dts;
  for (std::size_t e = 0; e < estimate.size(); ++e) {
    const double t = estimate[e].t + options.time_offset;
    const auto r = reference.nearest(t, options.max_time_diff);
    if (!r) continue;
    const double dt = std::abs(reference[*r].t - t);
    if (!pairs.empty() && pairs.back().ref >= *r) {
      // Both sequences are sorted, so a clash can only be with the last accepted pair.
      if (pairs.back().ref == *r && dt < dts.back()) {
        pairs.back().est = e;
        dts.back() = dt;
      }
      continue;
    }
    pairs.push_back(PosePair{*r, e});
    dts.push_back(dt);
  }
  if (pairs.empty()) {
    throw InputError(eval_detail::format(
        "no overlap: reference spans [%.9g, %.9g], estimate spans [%.9g, %.9g] (time offset "
        "%.9g s): no pair of timestamps within %.9g s",
        reference.startTime(), reference.endTime(), estimate.startTime() + options.time_offset,
        estimate.endTime() + options.time_offset, options.time_offset, options.max_time_diff));
  }
  return pairs;
}

}  // namespace abi_v1
}  // namespace plugslam
