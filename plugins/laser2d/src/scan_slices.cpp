#include "scan_slices.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>

#include "plugslam/errors.h"

namespace plugslam {
namespace laser2d {

namespace {

// nanoflann's view of a cloud's points.
struct CloudAdaptor {
  const std::vector<Eigen::Vector2d>* points = nullptr;
  size_t kdtree_get_point_count() const { return points ? points->size() : 0; }
  double kdtree_get_pt(uint32_t i, size_t dim) const { return (*points)[i][dim]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

// The single nearest neighbour within a gate: starting with the gate as the worst distance
// lets the search prune every branch beyond it.
class NearestWithin {
 public:
  explicit NearestWithin(double max_sq) : dist_(max_sq) {}
  size_t size() const { return found_ ? 1 : 0; }
  bool full() const { return true; }
  bool addPoint(double dist, uint32_t index) {
    if (dist < dist_) {
      dist_ = dist;
      index_ = index;
      found_ = true;
    }
    return true;
  }
  double worstDist() const { return dist_; }
  bool found() const { return found_; }
  uint32_t index() const { return index_; }

 private:
  double dist_;
  uint32_t index_ = 0;
  bool found_ = false;
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CloudAdaptor>,
                                                 CloudAdaptor, 2, uint32_t>;

}  // namespace

struct ScanSliceBase::KdTree {
  CloudAdaptor adaptor;
  Tree index{2, adaptor,
             nanoflann::KDTreeSingleIndexAdaptorParams(
                 10, nanoflann::KDTreeSingleIndexAdaptorFlags::SkipInitialBuildIndex)};
};

ScanSliceBase::ScanSliceBase() : tree_(std::make_unique<KdTree>()) {}
ScanSliceBase::~ScanSliceBase() = default;

void ScanSliceBase::configure() {
  information_ = 1.0 / (sigma() * sigma());
  cos_normal_ = max_normal_angle() >= M_PI ? -2.0 : std::cos(max_normal_angle());
  kernel_.reset();
  // The kernel works on Mahalanobis errors: a scale in metres becomes scale / sigma.
  if (kernel() != "none") kernel_ = makeRobustKernel(kernel(), kernel_scale() / sigma());
  made_kernel_ = kernel();
  made_scale_ = kernel_scale();
  made_sigma_ = sigma();
  made_normal_angle_ = max_normal_angle();
}

bool ScanSliceBase::prepare(const AlignContext<Space2D>&) {
  // Parameters may have been changed after configure() (shell, hot swap): refresh the cache.
  if (kernel() != made_kernel_ || kernel_scale() != made_scale_ || sigma() != made_sigma_ ||
      max_normal_angle() != made_normal_angle_)
    configure();
  pairs_.clear();
  const PointCloud2D& measured = *measurement;
  const PointCloud2D& map = *scene;
  if (measured.empty() || map.empty()) return false;
  measured.checkConsistent();
  map.checkConsistent();
  if (association() == "kdtree" && (tree_->adaptor.points != &map.points ||
                                    tree_revision_ != map.revision || map.revision == 0)) {
    tree_->adaptor.points = &map.points;
    tree_->index.buildIndex();
    tree_revision_ = map.revision;
    ++tree_builds_;
  }
  pairs_.reserve(measured.size());
  point_information_.clear();
  if (range_sigma() > 0) {
    const double s2 = sigma() * sigma(), k2 = range_sigma() * range_sigma();
    point_information_.reserve(measured.size());
    for (const Eigen::Vector2d& p : measured.points)
      point_information_.push_back(1.0 / (s2 + k2 * (p - measured.sensor_origin).squaredNorm()));
  }
  search_extent_ = 0;
  for (const Eigen::Vector2d& p : measured.points)
    if (p.norm() <= search_range()) search_extent_ = std::max(search_extent_, p.norm());
  scorer_.reset();
  return true;
}

double ScanSliceBase::angularStep(double resolution) const {
  return search_extent_ > 0 ? angularStepAt(search_extent_, resolution) : 0.0;
}

bool ScanSliceBase::beginSearch(const SearchLattice<Space2D>& lattice) {
  scorer_.reset();
  const double r = lattice.resolution;
  const std::vector<Eigen::Vector2d> query =
      correlativeQuery(measurement->points, search_range(), r);
  if (query.empty()) return false;
  // Only the part of the scene the scan can reach from the window is rasterized.
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(search_extent_ + (lattice.cells + 1) * r);
  const Eigen::Vector2d c = lattice.center.translation();
  grid_ = std::make_unique<CorrelativeGrid>(scene->points, scene->normals, point_extent(), r,
                                            lattice.levels, c - reach, c + reach);
  scorer_ = std::make_unique<GridScorer>(*grid_, query, lattice);
  return true;
}

void ScanSliceBase::associate(const Pose& t) {
  pairs_.clear();
  if (!measurement.bound() || !scene.bound()) return;
  if (association() == "projective")
    associateProjective(t);
  else
    associateKdTree(t);
}

void ScanSliceBase::accept(int i, int j, const Eigen::Vector2d& point_in_scene,
                           const Eigen::Vector2d& normal_in_scene) {
  if (normal_in_scene.dot(scene->normals[j]) < cos_normal_) return;
  if (max_tangential() > 0) {
    const Eigen::Vector2d& n = scene->normals[j];
    const Eigen::Vector2d d = point_in_scene - scene->points[j];
    if (std::abs(n.x() * d.y() - n.y() * d.x()) > max_tangential()) return;
  }
  pairs_.emplace_back(i, j);
}

void ScanSliceBase::associateKdTree(const Pose& t) {
  const double gate = max_distance() * max_distance();
  const Eigen::Matrix2d r = t.linear();
  const PointCloud2D& measured = *measurement;
  const size_t n = measured.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d q = t * measured.points[i];
    NearestWithin result(gate);
    tree_->index.findNeighbors(result, q.data(), nanoflann::SearchParams());
    if (result.found())
      accept(static_cast<int>(i), static_cast<int>(result.index()), q, r * measured.normals[i]);
  }
}

void ScanSliceBase::associateProjective(const Pose& t) {
  const double res = projective_resolution();
  const int bins = static_cast<int>(std::ceil(2 * M_PI / res));
  bin_index_.assign(bins, -1);
  bin_range_.assign(bins, std::numeric_limits<double>::infinity());
  auto binOf = [&](const Eigen::Vector2d& v) {
    const int b = static_cast<int>((std::atan2(v.y(), v.x()) + M_PI) / res);
    return b < 0 ? 0 : (b >= bins ? bins - 1 : b);
  };
  // Scene in the robot frame at T; each bearing keeps its closest (visible) point.
  const Pose inv = t.inverse();
  const PointCloud2D& map = *scene;
  const PointCloud2D& measured = *measurement;
  const size_t m = map.size();
  for (size_t j = 0; j < m; ++j) {
    const Eigen::Vector2d v = inv * map.points[j];
    const int b = binOf(v);
    const double range = v.squaredNorm();
    if (range < bin_range_[b]) {
      bin_range_[b] = range;
      bin_index_[b] = static_cast<int>(j);
    }
  }
  const double gate = max_distance() * max_distance();
  const Eigen::Matrix2d r = t.linear();
  const size_t n = measured.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = measured.points[i];
    const Eigen::Vector2d q = t * p;
    const int b = binOf(p);
    int best = -1;
    double best_d = gate;
    for (int db = -1; db <= 1; ++db) {
      const int j = bin_index_[(b + db + bins) % bins];
      if (j < 0) continue;
      const double d = (map.points[j] - q).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = j;
      }
    }
    if (best >= 0) accept(static_cast<int>(i), best, q, r * measured.normals[i]);
  }
}

void PointToLineSlice::linearize(const Pose& t, NormalEquations<Space2D>& eq) const {
  const PointCloud2D& measured = *measurement;
  const PointCloud2D& map = *scene;
  const Robust r = robust();
  eq.candidates += measured.size();  // every measured point was tried
  for (const auto& [i, k] : pairs_)
    eq.add(PointToLine2D{measured.points[i], map.points[k], map.normals[k]}, t, informationOf(i),
           r);
}

void PointToPointSlice::linearize(const Pose& t, NormalEquations<Space2D>& eq) const {
  const PointCloud2D& measured = *measurement;
  const PointCloud2D& map = *scene;
  const Robust r = robust();
  eq.candidates += measured.size();  // every measured point was tried
  for (const auto& [i, k] : pairs_)
    eq.add(PointToPoint2D{measured.points[i], map.points[k]}, t, informationOf(i), r);
}

}  // namespace laser2d
}  // namespace plugslam
