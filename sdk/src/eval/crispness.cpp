#include "plugslam/eval/crispness.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <nanoflann.hpp>
#include <thread>

#include "eval/text_file.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

// All scan points in the world frame, scan after scan, as nanoflann's dataset adaptor.
struct WorldCloud {
  std::vector<double> xy;          // x0 y0 x1 y1 ...
  std::vector<std::int32_t> scan;  // scan index of each point

  std::size_t kdtree_get_point_count() const { return scan.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t dim) const { return xy[2 * i + dim]; }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, WorldCloud>,
                                                 WorldCloud, 2, std::uint32_t>;

// Nearest neighbour restricted to scans far enough in index. The pruning bound starts at the
// radius and only shrinks on accepted points, so excluded near-duplicates from neighbouring scans
// are visited but never tighten the search wrongly.
class GapNearestResult {
 public:
  using DistanceType = double;
  using IndexType = std::uint32_t;
  using CountType = std::size_t;

  GapNearestResult(const std::int32_t* scan_of, std::int32_t scan, std::int32_t gap,
                   std::int32_t max_gap, double radius_sq)
      : scan_of_(scan_of), scan_(scan), gap_(gap), max_gap_(max_gap), best_sq_(radius_sq) {}

  std::size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return found_; }
  bool addPoint(double dist_sq, std::uint32_t index) {
    const std::int32_t apart = std::abs(scan_of_[index] - scan_);
    if (dist_sq < best_sq_ && apart >= gap_ && (max_gap_ == 0 || apart <= max_gap_)) {
      best_sq_ = dist_sq;
      found_ = true;
    }
    return true;
  }
  double worstDist() const { return best_sq_; }
  bool found() const { return found_; }

 private:
  const std::int32_t* scan_of_;
  std::int32_t scan_;
  std::int32_t gap_;
  std::int32_t max_gap_;
  double best_sq_;
  bool found_ = false;
};

}  // namespace

Eigen::Isometry2d planarPose(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d r = pose.linear();
  // Yaw of the rotation's x axis projected on the plane; exact for rotations about z.
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  Eigen::Isometry2d out = Eigen::Isometry2d::Identity();
  out.linear() = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  out.translation() = pose.translation().head<2>();
  return out;
}

std::vector<PosedScan> placeScans(const std::vector<std::vector<Eigen::Vector2d>>& points,
                                  const std::vector<double>& stamps, const Trajectory& trajectory,
                                  double max_time_diff) {
  if (points.size() != stamps.size()) {
    throw InputError(eval_detail::format("placeScans: %zu scans but %zu timestamps", points.size(),
                                         stamps.size()));
  }
  std::vector<PosedScan> out(points.size());
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto i = trajectory.nearest(stamps[k], max_time_diff);
    if (!i) {
      throw InputError(eval_detail::format(
          "scan %zu (t = %.9g) has no trajectory pose within %.9g s (trajectory spans [%.9g, "
          "%.9g]): expected one pose per scan",
          k, stamps[k], max_time_diff, trajectory.empty() ? 0.0 : trajectory.startTime(),
          trajectory.empty() ? 0.0 : trajectory.endTime()));
    }
    out[k].points = points[k];
    out[k].pose = planarPose(trajectory[*i].pose);
  }
  return out;
}

CrispnessResult computeCrispness(const std::vector<PosedScan>& scans,
                                 const CrispnessOptions& options) {
  if (!(options.radius > 0.0) || !std::isfinite(options.radius)) {
    throw InputError("crispness radius must be a positive number of metres");
  }
  if (options.min_index_gap < 1) throw InputError("crispness min_index_gap must be at least 1");
  if (options.max_index_gap != 0 && options.max_index_gap < options.min_index_gap)
    throw InputError("crispness max_index_gap must be 0 (no limit) or at least min_index_gap");
  if (scans.size() > static_cast<std::size_t>(INT32_MAX)) {
    throw InputError("crispness: too many scans");
  }
  CrispnessResult result;
  result.scans = scans.size();
  result.min_index_gap = options.min_index_gap;
  result.max_index_gap = options.max_index_gap;
  result.radius = options.radius;

  WorldCloud cloud;
  std::size_t total = 0;
  for (const PosedScan& s : scans) total += s.points.size();
  if (total >= static_cast<std::size_t>(UINT32_MAX)) {
    throw InputError("crispness: too many points (more than 2^32)");
  }
  cloud.xy.reserve(2 * total);
  cloud.scan.reserve(total);
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const PosedScan& s = scans[k];
    if (!s.pose.matrix().allFinite()) {
      throw InputError(eval_detail::format("crispness: scan %zu has a non-finite pose", k));
    }
    for (const Eigen::Vector2d& p : s.points) {
      if (!p.allFinite()) {
        throw InputError(eval_detail::format("crispness: scan %zu has a non-finite point", k));
      }
      const Eigen::Vector2d w = s.pose * p;
      cloud.xy.push_back(w.x());
      cloud.xy.push_back(w.y());
      cloud.scan.push_back(static_cast<std::int32_t>(k));
    }
  }
  result.points = total;
  if (total == 0) return result;

  Tree tree(2, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();

  std::vector<double> nearest(total, -1.0);
  const double radius_sq = options.radius * options.radius;
  auto work = [&](std::size_t begin, std::size_t end) {
    const nanoflann::SearchParams params;
    for (std::size_t i = begin; i < end; ++i) {
      GapNearestResult r(cloud.scan.data(), cloud.scan[i], options.min_index_gap,
                         options.max_index_gap, radius_sq);
      tree.findNeighbors(r, &cloud.xy[2 * i], params);
      if (r.found()) nearest[i] = std::sqrt(r.worstDist());
    }
  };
  const std::size_t threads = std::max<std::size_t>(
      1, std::min<std::size_t>(static_cast<std::size_t>(std::max(1, options.threads)),
                               total / 1024 + 1));
  if (threads == 1) {
    work(0, total);
  } else {
    std::vector<std::thread> pool;
    const std::size_t chunk = (total + threads - 1) / threads;
    for (std::size_t t = 0; t < threads; ++t) {
      const std::size_t b = t * chunk, e = std::min(total, b + chunk);
      if (b < e) pool.emplace_back(work, b, e);
    }
    for (std::thread& th : pool) th.join();
  }
  // Summed in point order so the result does not depend on the thread count.
  double sum = 0.0;
  for (double d : nearest) {
    if (d >= 0.0) {
      sum += d;
      ++result.matched_points;
    }
  }
  result.mean = result.matched_points ? sum / static_cast<double>(result.matched_points) : 0.0;
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
