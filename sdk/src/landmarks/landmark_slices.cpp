#include "plugslam/landmarks/landmark_slices.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include <spdlog/spdlog.h>

#include "plugslam/landmarks/observation_factor.h"
#include "plugslam/landmarks/point_registration.h"

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

// Keypoint i as the landmark factor measures it: (u, v, 1/z) and the information of each (the
// inverse depth has none without `depth`).
struct KeypointObservation {
  Eigen::Vector3d measured;
  Eigen::Vector3d information;
};
KeypointObservation observationOf(const FeatureSet& f, size_t i, bool depth) {
  const double wp = 1.0 / (f.pixel_sigma[i] * f.pixel_sigma[i]);
  const double wq = depth ? 1.0 / (f.inverse_depth_sigma[i] * f.inverse_depth_sigma[i]) : 0.0;
  return {Eigen::Vector3d(f.pixels[i].x(), f.pixels[i].y(), depth ? f.inverse_depth[i] : 0.0),
          Eigen::Vector3d(wp, wp, wq)};
}
}  // namespace

template <class S>
typename LandmarkReprojection<S>::Error LandmarkReprojection<S>::error(
    const typename S::Pose& t) const {
  Error e = Error::Zero();
  observationError(S::to3D(t), mount, camera, point, measured, e, nullptr, nullptr);
  return e;
}

template <class S>
bool LandmarkReprojection<S>::errorAndJacobian(const typename S::Pose& t, Error& e,
                                               Jacobian& j) const {
  Eigen::Matrix<double, 3, 6> jp;
  if (!observationError(S::to3D(t), mount, camera, point, measured, e, &jp, nullptr)) return false;
  j = restrictJacobian<S>(jp);
  return true;
}

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
void ReprojectionSlice<S>::spreadWindows(const AlignContext<S>& context) {
  const LandmarkMap& map = *scene;
  const FeatureSet& f = *measurement;
  prior_covered_ = true;
  if (!context.covariance) {
    spread_.assign(map.size(), search_radius() - refine_radius());
    return;
  }
  // The projection's covariance is J Sigma J^T, J the (u, v) rows of the observation's Jacobian
  // w.r.t. the robot pose at the prediction; the window reaches search_sigmas standard
  // deviations along its longest axis.
  spread_.assign(map.size(), 0.0);
  const Eigen::Isometry3d robot = S::to3D(context.guess);
  const typename S::Matrix& sigma = *context.covariance;
  size_t visible = 0, beyond = 0;
  for (size_t j = 0; j < map.size(); ++j) {
    Eigen::Vector3d e;
    Eigen::Matrix<double, 3, 6> jp;
    if (!observationError(robot, f.mount, f.camera, map.positions[j], Eigen::Vector3d::Zero(), e,
                          &jp, nullptr))
      continue;
    const double u = e.x(), v = e.y();  // the projection (measured is zero)
    const Eigen::Matrix<double, 2, S::kDof> jr =
        restrictJacobian<S>(jp).template topRows<2>();
    const Eigen::Matrix2d projected = jr * sigma * jr.transpose();
    const double half_trace = 0.5 * (projected(0, 0) + projected(1, 1));
    const double half_diff = 0.5 * (projected(0, 0) - projected(1, 1));
    const double largest = half_trace + std::hypot(half_diff, projected(0, 1));
    const double reach = context.search_sigmas * std::sqrt(std::max(0.0, largest));
    spread_[j] = std::min(max_search_radius(), reach);
    if (u < 0 || v < 0 || u > f.width - 1 || v > f.height - 1) continue;
    ++visible;
    if (reach > max_search_radius()) ++beyond;
  }
  prior_covered_ = visible > 0 && 2 * beyond < visible;
}

template <class S>
bool ReprojectionSlice<S>::prepare(const AlignContext<S>& context) {
  if (kernel() != made_kernel_ || kernel_scale() != made_scale_) configure();
  matched_ += matches_.size();  // the previous frame's association at its solution
  matches_.clear();
  round_ = 0;
  if (measurement->empty() || scene->empty()) return false;
  Stopwatch watch(time_s_);
  measurement->checkConsistent();
  scene->checkConsistent();
  grid_.build(*measurement);
  spreadWindows(context);
  ++frames_;
  return true;
}

template <class S>
void ReprojectionSlice<S>::associate(const Pose& t) {
  matches_.clear();
  if (!measurement.bound() || !scene.bound()) return;
  Stopwatch watch(time_s_);
  AssociationOptions o;
  // Each round starts nearer the solution: what the pose's uncertainty adds to the window halves.
  o.radius = refine_radius();
  o.spread = &spread_;
  o.spread_scale = 1.0 / static_cast<double>(1 << std::min(round_, 20));
  o.max_hamming = max_hamming();
  o.ratio = ratio();
  o.scale_tolerance = scale_tolerance();
  ++round_;
  grid_.associate(*scene, S::to3D(t) * measurement->mount, o, matches_);
}

template <class S>
void ReprojectionSlice<S>::linearize(const Pose& t, NormalEquations<S>& eq) const {
  if (!measurement.bound() || !scene.bound()) return;
  Stopwatch watch(time_s_);
  const FeatureSet& f = *measurement;
  eq.candidates += f.size();
  for (const LandmarkMatch& m : matches_) {
    const size_t i = static_cast<size_t>(m.feature);
    const bool depth = use_depth() && f.hasDepth(i);
    const KeypointObservation o = observationOf(f, i, depth);
    const double wp = o.information.x(), wq = o.information.z();
    const LandmarkReprojection<S> factor{f.mount, f.camera, scene->positions[m.landmark],
                                         o.measured};
    // Inliers: within the chi-square 95 % band of the residual's dimensions.
    Robust robust{kernel_.get()};
    robust.inlier_chi2 = kInlierChi2[depth ? 3 : 2];
    if (!landmark_uncertainty()) {
      eq.addDiagonal(factor, t, o.information, robust);
      continue;
    }
    // The residual's covariance is the keypoint's plus the landmark's, carried into (u, v, 1/z)
    // by the projection's Jacobian at the current estimate: Sigma = Sigma_z + Jp Sigma_p Jp^T.
    Eigen::Vector3d e;
    Eigen::Matrix3d jp;
    if (!observationError(S::to3D(t), f.mount, f.camera, factor.point, factor.measured, e,
                          nullptr, &jp))
      continue;
    const Eigen::Matrix3d projected = jp * scene->covariances[m.landmark] * jp.transpose();
    typename NormalEquations<S>::template Information<3> information =
        NormalEquations<S>::template Information<3>::Zero();
    if (depth) {
      Eigen::Matrix3d sigma = projected;
      sigma.diagonal() += Eigen::Vector3d(1.0 / wp, 1.0 / wp, 1.0 / wq);
      information = sigma.inverse();
    } else {  // no depth: the (u, v) block only, 1/z keeps no weight
      Eigen::Matrix2d sigma = projected.template topLeftCorner<2, 2>();
      sigma.diagonal().array() += 1.0 / wp;
      information.template topLeftCorner<2, 2>() = sigma.inverse();
    }
    eq.add(factor, t, information, robust);
  }
}

template <class S>
std::optional<typename ReprojectionSlice<S>::Pose> ReprojectionSlice<S>::recoverPose() {
  if (!measurement.bound() || !scene.bound()) return std::nullopt;
  Stopwatch watch(recovery_s_);
  ++recoveries_tried_;
  DescriptorMatchOptions mo;
  mo.max_hamming = recover_max_hamming();
  mo.ratio = recover_ratio();
  RansacOptions ro;
  ro.min_inliers = recover_min_inliers();
  ro.seed = frames_;  // repeatable run to run, different frame to frame
  const PointRegistration r =
      registerPoints(describedPoints(*measurement), describedPoints(*scene), mo, ro);
  spdlog::debug("{}: recovery: {} descriptor matches, {} RANSAC inliers{}", this->name(),
                r.matches, r.inliers.size(), r.valid ? "" : " (no pose)");
  if (!r.valid) return std::nullopt;
  ++recoveries_;
  // scene <- camera, and the camera is at `mount` in the robot frame.
  return S::from3D(r.target_from_source * measurement->mount.inverse());
}

template <class S>
std::vector<Statistic> ReprojectionSlice<S>::statistics() const {
  return {{"frames", static_cast<double>(frames_)},
          {"alignment_s", time_s_},
          {"matches_per_frame", perFrame(matched_ + matches_.size(), frames_)},
          {"recoveries_tried", static_cast<double>(recoveries_tried_)},
          {"recoveries", static_cast<double>(recoveries_)},
          {"recovery_s", recovery_s_}};
}

template <class S>
std::vector<Statistic> LandmarkMapSlice<S>::statistics() const {
  return {{"frames", static_cast<double>(frames_)},
          {"merge_s", time_s_},
          {"matched_per_frame", perFrame(matched_, frames_)},
          {"created_per_frame", perFrame(created_, frames_)},
          {"pruned_per_frame", perFrame(pruned_, frames_)},
          {"landmarks_per_frame", perFrame(landmarks_, frames_)},
          {"bundles", static_cast<double>(bundles_)},
          {"bundle_s", bundle_s_}};
}

template <class S>
void LandmarkMapSlice<S>::bundle(const MergeContext<S>& context, const FeatureSet& f,
                                 LandmarkMap& map,
                                 const std::vector<std::pair<size_t, uint64_t>>& observed) {
  BundleFrame frame;
  frame.seq = context.seq;
  frame.pose = S::to3D(context.pose);
  frame.mount = f.mount;
  frame.camera = f.camera;
  frame.observations.reserve(observed.size());
  for (const auto& [i, id] : observed) {
    const KeypointObservation o = observationOf(f, i, f.hasDepth(i));
    frame.observations.push_back(BundleObservation{id, o.measured, o.information});
  }
  bundle_.push_back(std::move(frame));
  // Frames before the last bundle_frames stay in the bundle, fixed, for their observations: a
  // landmark seen long before keeps what those frames said of it (its place is not re-decided
  // by the last few views alone).
  const size_t window = static_cast<size_t>(bundle_frames());
  while (bundle_.size() > kBundleHistory * window) bundle_.erase(bundle_.begin());
  if (bundle_.size() < 2 || frames_ % static_cast<uint64_t>(bundle_every()) != 0) return;
  Stopwatch watch(bundle_s_);
  // The oldest frame ties the bundle to the poses before it: it stays. The frame just merged
  // moves with the others of the window, and the tracker takes its refined pose. A planar robot's
  // poses are the tracker's own: only the landmarks move.
  for (size_t k = 0; k < bundle_.size(); ++k)
    bundle_[k].fixed = S::kDim == 2 || k == 0 || k + window < bundle_.size();
  const BundleResult r = adjustBundle(bundle_, map);
  ++bundles_;
  if constexpr (S::kDim == 3)
    if (r.chi2_after < r.chi2_before) refined_ = bundle_.back().pose;
}

template <class S>
void LandmarkMapSlice<S>::handOver(const PropertyContainer& previous, PropertyContainer& next,
                                   const Pose& origin, uint64_t seq) {
  const LandmarkMap* old = previous.find<LandmarkMap>(scene.name());
  LandmarkMap& map = next.emplace<LandmarkMap>(scene.name());
  if (!old) return;
  map.descriptor_bytes = old->descriptor_bytes;
  const Eigen::Isometry3d to_new = S::to3D(origin).inverse();
  const Eigen::Matrix3d r = to_new.linear();
  const size_t bytes = static_cast<size_t>(old->descriptor_bytes);
  for (size_t j = 0; j < old->size(); ++j) {
    if (old->last_seen[j] != seq) continue;
    map.positions.push_back(to_new * old->positions[j]);
    map.covariances.push_back(r * old->covariances[j] * r.transpose());
    map.ids.push_back(old->ids[j]);
    map.observations.push_back(old->observations[j]);
    map.visible.push_back(old->visible[j]);
    map.last_seen.push_back(old->last_seen[j]);
    map.colours.push_back(old->colours[j]);
    map.reference_distances.push_back(old->reference_distances[j]);
    map.descriptors.insert(map.descriptors.end(), old->descriptor(j), old->descriptor(j) + bytes);
  }
  map.touch();
  // The bundle's frames saw the landmarks carried over: they go on, in the new map's frame.
  if (bundle_map_ == old && old->revision == bundle_revision_) {
    for (BundleFrame& f : bundle_) f.pose = to_new * f.pose;
    bundle_map_ = &map;
    bundle_revision_ = map.revision;
  }
}

template <class S>
void LandmarkMapSlice<S>::integrate(const MergeContext<S>& context) {
  const Pose& t = context.pose;
  last_matched_ = last_created_ = last_pruned_ = 0;
  refined_.reset();
  const FeatureSet* f = measurement.get();
  if (f->empty()) return;
  Stopwatch watch(time_s_);
  f->checkConsistent();
  LandmarkMap* map = scene.get();
  if (!map) {
    map = &scene.getOrInsert();
    map->descriptor_bytes = f->descriptor_bytes;
  }
  map->checkConsistent();
  // The bundle's frames are those of the map this slice last merged into, as it left it (another
  // map, or one changed since, starts them over).
  if (map != bundle_map_ || map->revision != bundle_revision_) {
    bundle_.clear();
    bundle_map_ = map;
  }
  if (map->empty()) map->descriptor_bytes = f->descriptor_bytes;
  if (map->descriptor_bytes != f->descriptor_bytes)
    throw InputError("LandmarkMapSlice: the map's descriptors have " +
                     std::to_string(map->descriptor_bytes) + " bytes, the frame's " +
                     std::to_string(f->descriptor_bytes));
  for (uint64_t id : map->ids) next_id_ = std::max(next_id_, id + 1);

  const Eigen::Isometry3d camera = S::to3D(t) * f->mount;
  const Eigen::Matrix3d r = camera.linear();
  const Eigen::Isometry3d to_camera = camera.inverse();
  AssociationOptions o;
  o.radius = match_radius();
  o.max_hamming = max_hamming();
  o.scale_tolerance = scale_tolerance();
  grid_.build(*f);
  grid_.associate(*map, camera, o, matches_, &visible_);
  const size_t old_size = map->size();
  for (size_t j = 0; j < old_size; ++j)
    if (visible_[j]) ++map->visible[j];

  std::vector<bool> matched(f->size(), false);
  std::vector<std::pair<size_t, uint64_t>> observed;  // (keypoint, landmark track id)
  const size_t bytes = static_cast<size_t>(f->descriptor_bytes);
  for (const LandmarkMatch& m : matches_) {
    const size_t i = static_cast<size_t>(m.feature), j = static_cast<size_t>(m.landmark);
    matched[i] = true;
    observed.emplace_back(i, map->ids[j]);
    ++last_matched_;
    ++map->observations[j];
    if (!visible_[j]) ++map->visible[j];
    map->last_seen[j] = context.seq;
    map->colours[j] = f->colours[i];
    std::copy(f->descriptor(i), f->descriptor(i) + bytes, map->descriptor(j));
    // The descriptor is now the one taken at this keypoint's scale from here.
    const double distance = (to_camera * map->positions[j]).norm();
    map->reference_distances[j] = distance * f->scales[i];
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
    observed.emplace_back(i, next_id_);
    map->push(camera * f->points[i], r * f->covariances[i] * r.transpose(), next_id_++,
              f->descriptor(i), f->colours[i], context.seq,
              f->points[i].norm() * f->scales[i]);
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
  if (bundle_frames() > 0) bundle(context, *f, *map, observed);
  bundle_revision_ = map->revision;
  ++frames_;
  matched_ += last_matched_;
  created_ += last_created_;
  pruned_ += last_pruned_;
  landmarks_ += map->size();
}

template struct LandmarkReprojection<Space2D>;
template struct LandmarkReprojection<Space3D>;
template class ReprojectionSlice<Space2D>;
template class ReprojectionSlice<Space3D>;
template class LandmarkMapSlice<Space2D>;
template class LandmarkMapSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
