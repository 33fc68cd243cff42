#include "plugslam/landmarks/landmark_slices.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "plugslam/landmarks/observation_factor.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
// Chi-square 95 % quantiles: the inlier band of a residual with 2 (no depth) or 3 dimensions.
constexpr double kInlierChi2[4] = {0.0, 3.841, 5.991, 7.815};

// Columns of the SE3 tangent (x, y, z, rx, ry, rz) a pose space moves: all six in 3D, (x, y, rz)
// for a planar robot (its tangent is (x, y, theta)).
template <class S>
typename Eigen::Matrix<double, 3, S::kDof> restrictJacobian(const Eigen::Matrix<double, 3, 6>& j) {
  if constexpr (S::kDim == 3) {
    return j;
  } else {
    Eigen::Matrix<double, 3, 3> out;
    out.col(0) = j.col(0);
    out.col(1) = j.col(1);
    out.col(2) = j.col(5);
    return out;
  }
}
}  // namespace

template <class S>
ReprojectionSlice<S>::ReprojectionSlice() = default;
template <class S>
ReprojectionSlice<S>::~ReprojectionSlice() = default;

template <class S>
void ReprojectionSlice<S>::configure() {
  if (refine_radius() > search_radius())
    throw ParamError("refine_radius", "must not exceed search_radius (" +
                                          std::to_string(search_radius()) + " px)");
  kernel_.reset();
  if (kernel() != "none") kernel_ = makeRobustKernel(kernel(), kernel_scale());
  made_kernel_ = kernel();
  made_scale_ = kernel_scale();
}

template <class S>
bool ReprojectionSlice<S>::bind(const Frame& frame, const PropertyContainer& scene_container,
                                const AlignContext<S>&) {
  if (kernel() != made_kernel_ || kernel_scale() != made_scale_) configure();
  features_ = frame.measurement.find<FeatureSet>(measurement());
  landmarks_ = scene_container.find<LandmarkMap>(scene());
  matches_.clear();
  round_ = 0;
  if (!features_ || !landmarks_ || features_->empty() || landmarks_->empty()) return false;
  features_->checkConsistent();
  landmarks_->checkConsistent();
  grid_.build(*features_);
  return true;
}

template <class S>
void ReprojectionSlice<S>::associate(const Pose& t) {
  matches_.clear();
  if (!features_ || !landmarks_) return;
  AssociationOptions o;
  // Each round starts nearer the solution: the radius halves down to refine_radius.
  o.radius = std::max(refine_radius(), search_radius() / static_cast<double>(1 << std::min(round_, 20)));
  o.max_hamming = max_hamming();
  o.ratio = ratio();
  ++round_;
  grid_.associate(*landmarks_, S::to3D(t) * features_->mount, o, matches_);
}

template <class S>
void ReprojectionSlice<S>::linearize(const Pose& t, NormalEquations<S>& eq) const {
  if (!features_ || !landmarks_) return;
  const FeatureSet& f = *features_;
  eq.candidates += f.size();
  const Eigen::Isometry3d t3 = S::to3D(t);
  Eigen::Vector3d e;
  Eigen::Matrix<double, 3, 6> jp;
  for (const LandmarkMatch& m : matches_) {
    const size_t i = static_cast<size_t>(m.feature);
    const bool depth = use_depth() && f.hasDepth(i);
    const Eigen::Vector3d measured(f.pixels[i].x(), f.pixels[i].y(), depth ? f.inverse_depth[i] : 0);
    if (!observationError(t3, f.mount, f.camera, landmarks_->positions[m.landmark], measured, e, &jp,
                          nullptr))
      continue;
    const double wp = 1.0 / (f.pixel_sigma[i] * f.pixel_sigma[i]);
    const double wq = depth ? 1.0 / (f.inverse_depth_sigma[i] * f.inverse_depth_sigma[i]) : 0.0;
    const Eigen::Vector3d info(wp, wp, wq);
    const double s = e.dot(info.cwiseProduct(e));
    ++eq.factors;
    if (s <= kInlierChi2[depth ? 3 : 2]) ++eq.inliers;
    double w = 1.0;
    if (kernel_) {
      const Eigen::Vector3d rho = kernel_->robustify(s);
      eq.chi2 += rho[0];
      w = rho[1];
    } else {
      eq.chi2 += s;
    }
    const auto j = restrictJacobian<S>(jp);
    const auto jt_w = (j.transpose() * (w * info).asDiagonal()).eval();
    eq.H.noalias() += jt_w * j;
    eq.b.noalias() += jt_w * e;
  }
}

template <class S>
void LandmarkMapSlice<S>::merge(const Frame& frame, PropertyContainer& scene_container,
                                const Pose& t) {
  last_matched_ = last_created_ = last_pruned_ = 0;
  const FeatureSet* f = frame.measurement.find<FeatureSet>(measurement());
  if (!f || f->empty()) return;
  f->checkConsistent();
  LandmarkMap* map = scene_container.find<LandmarkMap>(scene());
  if (!map) {
    map = &scene_container.emplace<LandmarkMap>(scene());
    map->descriptor_bytes = f->descriptor_bytes;
  }
  map->checkConsistent();
  if (map->empty()) map->descriptor_bytes = f->descriptor_bytes;
  if (map->descriptor_bytes != f->descriptor_bytes)
    throw InputError("LandmarkMapSlice: the map's descriptors have " +
                     std::to_string(map->descriptor_bytes) + " bytes, the frame's " +
                     std::to_string(f->descriptor_bytes));
  for (uint64_t id : map->ids) next_id_ = std::max(next_id_, id + 1);

  const Eigen::Isometry3d camera = S::to3D(t) * f->mount;
  const Eigen::Matrix3d r = camera.linear();
  AssociationOptions o;
  o.radius = match_radius();
  o.max_hamming = max_hamming();
  grid_.build(*f);
  grid_.associate(*map, camera, o, matches_, &visible_);
  const size_t old_size = map->size();
  for (size_t j = 0; j < old_size; ++j)
    if (visible_[j]) ++map->visible[j];

  std::vector<bool> matched(f->size(), false);
  const size_t bytes = static_cast<size_t>(f->descriptor_bytes);
  for (const LandmarkMatch& m : matches_) {
    const size_t i = static_cast<size_t>(m.feature), j = static_cast<size_t>(m.landmark);
    matched[i] = true;
    ++last_matched_;
    ++map->observations[j];
    if (!visible_[j]) ++map->visible[j];
    map->last_seen[j] = frame.seq;
    map->colours[j] = f->colours[i];
    std::copy(f->descriptor(i), f->descriptor(i) + bytes, map->descriptor(j));
    if (!f->hasDepth(i)) continue;
    // Information-weighted fusion of the two Gaussian estimates of the point.
    const Eigen::Vector3d p = camera * f->points[i];
    const Eigen::Matrix3d c = r * f->covariances[i] * r.transpose();
    const Eigen::Matrix3d& cl = map->covariances[j];
    const Eigen::Vector3d d = p - map->positions[j];
    Eigen::LDLT<Eigen::Matrix3d> sum(cl + c);
    if (sum.info() != Eigen::Success || !sum.isPositive()) continue;
    if (d.dot(sum.solve(d)) > fusion_gate()) continue;
    const Eigen::Matrix3d gain = cl * sum.solve(Eigen::Matrix3d::Identity());
    map->positions[j] += gain * d;
    map->covariances[j] = (Eigen::Matrix3d::Identity() - gain) * cl;
    map->covariances[j] = 0.5 * (map->covariances[j] + map->covariances[j].transpose()).eval();
  }
  for (size_t i = 0; i < f->size(); ++i) {
    if (matched[i] || !f->hasDepth(i)) continue;
    if (max_depth() > 0 && f->points[i].z() > max_depth()) continue;
    map->push(camera * f->points[i], r * f->covariances[i] * r.transpose(), next_id_++,
              f->descriptor(i), f->colours[i], frame.seq);
    ++last_created_;
  }
  std::vector<bool> keep(map->size(), true);
  for (size_t j = 0; j < old_size; ++j)
    if (map->visible[j] >= static_cast<uint32_t>(prune_after()) &&
        map->observations[j] < min_found_ratio() * map->visible[j]) {
      keep[j] = false;
      ++last_pruned_;
    }
  if (last_pruned_ > 0)
    map->keepOnly(keep);
  else
    map->touch();
}

template class ReprojectionSlice<Space2D>;
template class ReprojectionSlice<Space3D>;
template class LandmarkMapSlice<Space2D>;
template class LandmarkMapSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
