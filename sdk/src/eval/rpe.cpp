#include "plugslam/eval/rpe.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "eval/text_file.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;
}  // namespace

std::string toString(RpeUnit unit) {
  switch (unit) {
    case RpeUnit::Frames:
      return "frames";
    case RpeUnit::Meters:
      return "m";
    case RpeUnit::Seconds:
      return "s";
  }
  return "frames";
}

RpeUnit parseRpeUnit(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (n == "frames" || n == "f") return RpeUnit::Frames;
  if (n == "m" || n == "meters" || n == "metres") return RpeUnit::Meters;
  if (n == "s" || n == "seconds") return RpeUnit::Seconds;
  throw InputError("unknown RPE unit '" + name + "': expected frames, m or s");
}

RpeResult computeRpe(const Trajectory& reference, const Trajectory& estimate,
                     const RpeOptions& options) {
  if (!(options.delta > 0.0) || !std::isfinite(options.delta)) {
    throw InputError("RPE delta must be a positive number");
  }
  if (options.unit == RpeUnit::Frames && options.delta != std::floor(options.delta)) {
    throw InputError("RPE delta in frames must be a whole number");
  }
  const std::vector<PosePair> pairs = associate(reference, estimate, options.association);
  const std::size_t n = pairs.size();
  // Distances along the associated reference poses, so a segment's length ignores poses the
  // estimate does not have.
  std::vector<double> dist(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    dist[k] = dist[k - 1] + (reference[pairs[k].ref].pose.translation() -
                             reference[pairs[k - 1].ref].pose.translation())
                                .norm();
  }
  auto endOf = [&](std::size_t i) -> std::size_t {
    switch (options.unit) {
      case RpeUnit::Frames:
        return i + static_cast<std::size_t>(options.delta);
      case RpeUnit::Meters: {
        const auto it = std::lower_bound(dist.begin() + static_cast<std::ptrdiff_t>(i), dist.end(),
                                         dist[i] + options.delta);
        return static_cast<std::size_t>(it - dist.begin());
      }
      case RpeUnit::Seconds: {
        std::size_t j = i + 1;
        const double t0 = reference[pairs[i].ref].t;
        while (j < n && reference[pairs[j].ref].t - t0 < options.delta) ++j;
        return j;
      }
    }
    return n;
  };
  std::vector<double> trans, rot, percent, length;
  std::vector<RpeSegment> segments;
  std::size_t i = 0;
  while (i < n) {
    const std::size_t j = endOf(i);
    if (j >= n) break;
    const Eigen::Isometry3d& qi = reference[pairs[i].ref].pose;
    const Eigen::Isometry3d& qj = reference[pairs[j].ref].pose;
    const Eigen::Isometry3d& pi = estimate[pairs[i].est].pose;
    const Eigen::Isometry3d& pj = estimate[pairs[j].est].pose;
    const Eigen::Isometry3d e = (qi.inverse() * qj).inverse() * (pi.inverse() * pj);
    trans.push_back(e.translation().norm());
    rot.push_back(Eigen::AngleAxisd(e.linear()).angle() * kRadToDeg);
    const double travelled = dist[j] - dist[i];
    length.push_back(travelled);
    if (travelled > 0) percent.push_back(100.0 * trans.back() / travelled);
    segments.push_back({pairs[i], pairs[j], trans.back(), rot.back(), travelled});
    i = options.all_pairs ? i + 1 : j;
  }
  if (trans.empty()) {
    throw InputError(eval_detail::format(
        "RPE: no segment of %.9g %s among %zu associated poses (reference path %.6g m over "
        "%.6g s)",
        options.delta, toString(options.unit).c_str(), n, n ? dist.back() : 0.0,
        reference[pairs.back().ref].t - reference[pairs.front().ref].t));
  }
  RpeResult result;
  result.unit = options.unit;
  result.delta = options.delta;
  result.pairs = trans.size();
  result.translation = computeErrorStats(trans);
  result.rotation_deg = computeErrorStats(rot);
  result.length_m = computeErrorStats(length);
  result.segments = std::move(segments);
  if (!percent.empty()) result.translation_percent = computeErrorStats(percent);
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
