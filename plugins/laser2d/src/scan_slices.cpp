#include "scan_slices.h"

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

bool ScanSliceBase::bind(const Frame& frame, const PropertyContainer& scene_container,
                         const AlignContext<Space2D>&) {
  // Parameters may have been changed after configure() (shell, hot swap): refresh the cache.
  if (kernel() != made_kernel_ || kernel_scale() != made_scale_ || sigma() != made_sigma_ ||
      max_normal_angle() != made_normal_angle_)
    configure();
  measured_ = frame.measurement.find<PointCloud2D>(measurement());
  scene_ = scene_container.find<PointCloud2D>(scene());
  pairs_.clear();
  if (!measured_ || !scene_ || measured_->empty() || scene_->empty()) return false;
  measured_->checkConsistent();
  scene_->checkConsistent();
  if (association() == "kdtree" && (tree_->adaptor.points != &scene_->points ||
                                    tree_revision_ != scene_->revision || scene_->revision == 0)) {
    tree_->adaptor.points = &scene_->points;
    tree_->index.buildIndex();
    tree_revision_ = scene_->revision;
    ++tree_builds_;
  }
  pairs_.reserve(measured_->size());
  point_information_.clear();
  if (range_sigma() > 0) {
    const double s2 = sigma() * sigma(), k2 = range_sigma() * range_sigma();
    point_information_.reserve(measured_->size());
    for (const Eigen::Vector2d& p : measured_->points)
      point_information_.push_back(1.0 / (s2 + k2 * (p - measured_->sensor_origin).squaredNorm()));
  }
  return true;
}

void ScanSliceBase::associate(const Pose& t) {
  pairs_.clear();
  if (!measured_ || !scene_) return;
  if (association() == "projective")
    associateProjective(t);
  else
    associateKdTree(t);
}

void ScanSliceBase::accept(int i, int j, const Eigen::Vector2d& point_in_scene,
                           const Eigen::Vector2d& normal_in_scene) {
  if (normal_in_scene.dot(scene_->normals[j]) < cos_normal_) return;
  if (max_tangential() > 0) {
    const Eigen::Vector2d& n = scene_->normals[j];
    const Eigen::Vector2d d = point_in_scene - scene_->points[j];
    if (std::abs(n.x() * d.y() - n.y() * d.x()) > max_tangential()) return;
  }
  pairs_.emplace_back(i, j);
}

void ScanSliceBase::associateKdTree(const Pose& t) {
  const double gate = max_distance() * max_distance();
  const Eigen::Matrix2d r = t.linear();
  const size_t n = measured_->size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d q = t * measured_->points[i];
    NearestWithin result(gate);
    tree_->index.findNeighbors(result, q.data(), nanoflann::SearchParams());
    if (result.found())
      accept(static_cast<int>(i), static_cast<int>(result.index()), q, r * measured_->normals[i]);
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
  const size_t m = scene_->size();
  for (size_t j = 0; j < m; ++j) {
    const Eigen::Vector2d v = inv * scene_->points[j];
    const int b = binOf(v);
    const double range = v.squaredNorm();
    if (range < bin_range_[b]) {
      bin_range_[b] = range;
      bin_index_[b] = static_cast<int>(j);
    }
  }
  const double gate = max_distance() * max_distance();
  const Eigen::Matrix2d r = t.linear();
  const size_t n = measured_->size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = measured_->points[i];
    const Eigen::Vector2d q = t * p;
    const int b = binOf(p);
    int best = -1;
    double best_d = gate;
    for (int db = -1; db <= 1; ++db) {
      const int j = bin_index_[(b + db + bins) % bins];
      if (j < 0) continue;
      const double d = (scene_->points[j] - q).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = j;
      }
    }
    if (best >= 0) accept(static_cast<int>(i), best, q, r * measured_->normals[i]);
  }
}

double ScanSliceBase::robustWeight(double s, double abs_error, NormalEquations<Space2D>& eq) const {
  ++eq.factors;
  if (abs_error <= kernel_scale()) ++eq.inliers;
  if (!kernel_) {
    eq.chi2 += s;
    return 1.0;
  }
  const Eigen::Vector3d rho = kernel_->robustify(s);
  eq.chi2 += rho[0];
  return rho[1];
}

void PointToLineSlice::errorAndJacobian(const Pose& t, const Eigen::Vector2d& p,
                                        const Eigen::Vector2d& q, const Eigen::Vector2d& n,
                                        double& e, Eigen::Matrix<double, 1, 3>& j) {
  const Eigen::Vector2d rp = t.linear() * p;
  e = n.dot(rp + t.translation() - q);
  const Eigen::Vector2d nr = t.linear().transpose() * n;
  j << nr.x(), nr.y(), n.y() * rp.x() - n.x() * rp.y();
}

void PointToLineSlice::linearize(const Pose& t, NormalEquations<Space2D>& eq) const {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 1, 3> j;
  double e;
  for (const auto& [i, k] : pairs_) {
    errorAndJacobian(t, measured_->points[i], scene_->points[k], scene_->normals[k], e, j);
    const double info = informationOf(i);
    const double w = robustWeight(e * e * info, std::abs(e), eq) * info;
    h.noalias() += w * j.transpose() * j;
    b.noalias() += w * e * j.transpose();
  }
  eq.H += h;
  eq.b += b;
}

void PointToPointSlice::errorAndJacobian(const Pose& t, const Eigen::Vector2d& p,
                                         const Eigen::Vector2d& q, Eigen::Vector2d& e,
                                         Eigen::Matrix<double, 2, 3>& j) {
  const Eigen::Vector2d rp = t.linear() * p;
  e = rp + t.translation() - q;
  j.leftCols<2>() = t.linear();
  j.col(2) = Eigen::Vector2d(-rp.y(), rp.x());
}

void PointToPointSlice::linearize(const Pose& t, NormalEquations<Space2D>& eq) const {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 2, 3> j;
  Eigen::Vector2d e;
  for (const auto& [i, k] : pairs_) {
    errorAndJacobian(t, measured_->points[i], scene_->points[k], e, j);
    const double sq = e.squaredNorm();
    const double info = informationOf(i);
    const double w = robustWeight(sq * info, std::sqrt(sq), eq) * info;
    h.noalias() += w * j.transpose() * j;
    b.noalias() += w * j.transpose() * e;
  }
  eq.H += h;
  eq.b += b;
}

}  // namespace laser2d
}  // namespace plugslam
