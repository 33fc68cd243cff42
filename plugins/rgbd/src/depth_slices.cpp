#include "depth_slices.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace plugslam {
namespace rgbd {

namespace {

// A keyframe is a view with its anchors: one object with the view's fields, so sessions written
// before anchors existed still load.
void saveFields(OutArchive& ar, const DepthView& v) {
  ar.field("depth", v.depth);
  ar.field("camera", v.camera);
  ar.field("pose", v.pose);
  ar.field("seq", v.seq);
}

void loadFields(InArchive& ar, DepthView& v) {
  ar.field("depth", v.depth);
  ar.field("camera", v.camera);
  ar.field("pose", v.pose);
  ar.field("seq", v.seq);
}

void checkSize(InArchive& ar, const DepthView& v) {
  if (!v.empty() && (v.camera.width != v.depth.width || v.camera.height != v.depth.height))
    ar.fail("depth keyframe: the camera's size differs from the depth image's");
}

bool apart(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double distance,
           double angle) {
  const Eigen::Isometry3d moved = a.inverse() * b;
  return moved.translation().norm() >= distance ||
         Eigen::AngleAxisd(moved.linear()).angle() >= angle;
}

}  // namespace

void save(OutArchive& ar, const DepthView& v) {
  ar.beginObject();
  saveFields(ar, v);
  ar.endObject();
}

void load(InArchive& ar, DepthView& v) {
  ar.beginObject();
  loadFields(ar, v);
  ar.endObject();
  checkSize(ar, v);
}

void save(OutArchive& ar, const DepthKeyframe& k) {
  ar.beginObject();
  saveFields(ar, k);
  ar.field("anchors", k.anchors);
  ar.endObject();
}

void load(InArchive& ar, DepthKeyframe& k) {
  ar.beginObject();
  loadFields(ar, k);
  k.anchors.clear();
  if (ar.hasKey("anchors")) ar.field("anchors", k.anchors);
  ar.endObject();
  checkSize(ar, k);
}

void subsampleDepth(const DepthImage& depth, const CameraIntrinsics& camera, int stride,
                    DepthImage& out_depth, CameraIntrinsics& out_camera) {
  const int s = std::max(1, stride);
  const int w = (depth.width + s - 1) / s, h = (depth.height + s - 1) / s;
  out_depth.stamp = depth.stamp;
  out_depth.resize(w, h);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      out_depth.data[static_cast<size_t>(v * w + u)] = depth.at(u * s, v * s);
  // Pixel u' of the subsampled image is pixel s u' of the original: u = fx x/z + cx = s u'.
  out_camera = camera;
  out_camera.fx = camera.fx / s;
  out_camera.fy = camera.fy / s;
  out_camera.cx = camera.cx / s;
  out_camera.cy = camera.cy / s;
  out_camera.width = w;
  out_camera.height = h;
}


template <class S>
typename DepthPointToPlane<S>::Error DepthPointToPlane<S>::error(const typename S::Pose& t) const {
  const Eigen::Isometry3d x = S::to3D(t);
  return Error(n.dot(x.linear() * p + x.translation() - q));
}

template <class S>
void DepthPointToPlane<S>::errorAndJacobian(const typename S::Pose& t, Error& e,
                                            Jacobian& j) const {
  const Eigen::Isometry3d x = S::to3D(t);
  e[0] = n.dot(x.linear() * p + x.translation() - q);
  // T <- T exp(delta): d e = n^T R (d_t + d_w x p) = (R^T n) . d_t + (p x R^T n) . d_w.
  const Eigen::Vector3d nr = x.linear().transpose() * n;
  const Eigen::Vector3d pw = p.cross(nr);
  if constexpr (S::kDim == 3) {
    j << nr.transpose(), pw.transpose();
  } else {
    j << nr.x(), nr.y(), pw.z();  // a planar robot moves x, y and the yaw
  }
}

template <class S>
DepthSlice<S>::DepthSlice() = default;
template <class S>
DepthSlice<S>::~DepthSlice() = default;

template <class S>
void DepthSlice<S>::configure() {
  kernel_ = makeRobustKernel("huber", kernel_scale());
  // Of the readings within one correlation window, the sampled ones share one error: each
  // sample weighs (stride / correlation)^2 of an independent reading.
  const double r = static_cast<double>(stride()) / correlation();
  information_scale_ = std::min(1.0, r * r);
}

template <class S>
bool DepthSlice<S>::prepare(const AlignContext<S>&) {
  if (!kernel_) configure();
  pairs_total_ += pairs_.size();  // the previous frame's association at its solution
  pairs_.clear();
  points_.clear();
  sigmas_.clear();
  round_ = 0;
  target_ = nullptr;
  depth_ = nullptr;
  if (scene->empty()) return false;
  Stopwatch watch(time_s_);
  const DepthKeyframe& k = *scene;
  // The keyframe's surface is built once per keyframe (it changes when the tracker slice takes
  // a new one or the map is a new one).
  if (k.seq != keyframe_seq_ || !k.pose.isApprox(keyframe_pose_) ||
      keyframe_.surface.width != k.depth.width) {
    keyframe_.surface = makeDepthSurface(k.depth, k.camera, 1);
    keyframe_.planes_found = false;
    keyframe_seq_ = k.seq;
    keyframe_pose_ = k.pose;
  }
  target_ = &keyframe_.surface;
  target_pose_ = keyframe_pose_;
  relocalised_ = false;
  registration_.prepare(*raw.camera);
  const DepthImage& d = registration_.apply(*raw.depth);
  depth_ = &d;
  const CameraInfo& c = *raw.camera;
  noise_ = depth_sigma.model();
  const int s = stride();
  for (int v = 0; v < d.height; v += s)
    for (int u = 0; u < d.width; u += s) {
      const double z = d.at(u, v);
      if (!(z > 0) || !std::isfinite(z)) continue;
      const Eigen::Vector3d pc((u - c.cx) / c.fx * z, (v - c.cy) / c.fy * z, z);
      points_.push_back(c.mount * pc);
      sigmas_.push_back(noise_.sigma(z));
    }
  ++frames_;
  points_total_ += points_.size();
  return !points_.empty();
}

template <class S>
void DepthSlice<S>::associate(const Pose& t) {
  pairs_.clear();
  vouched_ = 0;
  if (!scene.bound() || !target_ || target_->width == 0 || round_++ < first_round()) return;
  Stopwatch watch(time_s_);
  // Checked at every round's estimate, so a recovered pose near the keyframe gets the cue. A
  // view the frame's planes placed it against has passed a stronger test than nearness.
  const Eigen::Isometry3d to_target = target_pose_.inverse() * S::to3D(t);
  if (!relocalised_ &&
      (to_target * raw.camera->mount).translation().norm() > keyframe_distance())
    return;
  const double gate = max_distance();
  const DepthSurface& target = *target_;
  std::vector<double> residuals;  // point-to-plane, at t
  size_t judged = 0;              // readings that land where the target has a surface
  for (size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d x = to_target * points_[i];
    const long j = projectOnto(target, x);
    if (j < 0) continue;
    ++judged;
    const Eigen::Vector3f& n = target.normals[static_cast<size_t>(j)];
    const Eigen::Vector3d q = target.points[static_cast<size_t>(j)].cast<double>();
    const double sq = noise_.sigma(q.z());
    const double sigma = std::sqrt(sigmas_[i] * sigmas_[i] + sq * sq);
    // Far readings are noisier (2.6 cm at 4 m for a Kinect): the gate widens by three of the
    // pair's sigmas, or the far wall, the one surface that fixes the depth axis, drops out.
    if ((x - q).norm() > gate + 3.0 * sigma) continue;
    pairs_.push_back(Pair{static_cast<int>(i), target_pose_ * q,
                          target_pose_.linear() * n.cast<double>(), sigma});
    residuals.push_back(n.cast<double>().dot(x - q));
  }
  // Judged at each association's pose: the last one is the solution's. The keyframe is renewed
  // before the view moves far from it, so it saw nearly all of the frame's readings, and a pose
  // that slides the frame off it loses its vouch; a far view saw only part of them, and the
  // plane registration that chose it has already checked the whole frame against it.
  vouched_ = pinnedDirections(t, residuals, relocalised_ ? judged : points_.size());
}

template <class S>
void DepthSlice<S>::linearize(const Pose& t, NormalEquations<S>& eq) const {
  if (!scene.bound()) return;
  Stopwatch watch(time_s_);
  eq.candidates += points_.size();
  Robust robust{kernel_.get()};
  robust.inlier_bound = -1;  // pairs are not inliers one by one (see the class comment)
  for (const Pair& p : pairs_) {
    const DepthPointToPlane<S> f{points_[static_cast<size_t>(p.point)], p.q, p.n};
    eq.add(f, t, information_scale_ / (p.sigma * p.sigma), robust);
  }
  eq.inliers += static_cast<size_t>(vouched_);
}

template <class S>
int DepthSlice<S>::pinnedDirections(const Pose& t, const std::vector<double>& residuals,
                                    size_t readings) const {
  // The readings on the keyframe's surface, within the kernel's width: only they can vouch.
  std::vector<size_t> on;
  for (size_t k = 0; k < pairs_.size(); ++k)
    if (std::abs(residuals[k]) <= kernel_scale() * pairs_[k].sigma) on.push_back(k);
  if (on.empty() || static_cast<double>(on.size()) < vouch_share() * static_cast<double>(readings))
    return 0;
  // Their information, with a rotation of a rad in metres at their mean range (it moves the
  // readings by about that much), and their mean sigma. An even sample of a thousand readings
  // gives both to a few percent, and the test below has a wide margin either way (a pinned
  // direction of a room clears it ten times over, a free one has no information at all).
  const size_t step = std::max<size_t>(1, on.size() / 1000);
  typename S::Matrix h = S::Matrix::Zero();
  double range = 0, sigma = 0;
  size_t used = 0;
  typename DepthPointToPlane<S>::Error e;
  typename DepthPointToPlane<S>::Jacobian j;
  for (size_t k = 0; k < on.size(); k += step, ++used) {
    const Pair& p = pairs_[on[k]];
    const Eigen::Vector3d& x = points_[static_cast<size_t>(p.point)];
    DepthPointToPlane<S>{x, p.q, p.n}.errorAndJacobian(t, e, j);
    h.noalias() += j.transpose() * j * (information_scale_ / (p.sigma * p.sigma));
    range += x.norm();
    sigma += p.sigma;
  }
  h *= static_cast<double>(on.size()) / static_cast<double>(used);
  range /= static_cast<double>(used);
  sigma /= static_cast<double>(used);
  typename S::Matrix to_metres = S::Matrix::Identity();
  for (int i = S::kDof == 3 ? 2 : 3; i < S::kDof; ++i) to_metres(i, i) = 1.0 / range;
  const Eigen::SelfAdjointEigenSolver<typename S::Matrix> eig(to_metres * h * to_metres,
                                                              Eigen::EigenvaluesOnly);
  // Pinned: known at least as well as one reading knows its depth (information of at least
  // 1 / sigma^2). Along a surface the readings give next to none.
  int pinned = 0;
  for (int i = 0; i < S::kDof; ++i)
    if (eig.eigenvalues()(i) * sigma * sigma >= 1.0) ++pinned;
  return pinned;
}

template <class S>
const std::vector<DepthPlane>& DepthSlice<S>::planesOf(PlanarView& view) const {
  if (!view.planes_found) {
    view.planes = extractPlanes(view.surface, noise_);
    view.planes_found = true;
  }
  return view.planes;
}

template <class S>
std::optional<typename S::Pose> DepthSlice<S>::recoverPose() {
  if (!scene.bound() || !depth_ || !target_) return std::nullopt;
  Stopwatch watch(time_s_);
  const DepthKeyframe& k = *scene;
  const CameraInfo& c = *raw.camera;
  DepthImage depth;
  CameraIntrinsics camera;
  subsampleDepth(*depth_, c.intrinsics(), relocalise_stride(), depth, camera);
  camera.distortion = Distortion();  // registered depth is in the colour camera's ideal pinhole
  const DepthSurface frame = makeDepthSurface(depth, camera, 1);
  const std::vector<DepthPlane> frame_planes = extractPlanes(frame, noise_);
  if (frame_planes.size() < 3) return std::nullopt;
  // The anchors' surfaces are kept across frames (an anchor is the same view in every map it is
  // handed over to; only its pose is re-expressed), dropped once the keyframe no longer has them.
  for (auto it = anchors_.begin(); it != anchors_.end();) {
    const bool kept = std::any_of(k.anchors.begin(), k.anchors.end(),
                                  [&](const DepthView& a) { return a.seq == it->first; });
    it = kept ? std::next(it) : anchors_.erase(it);
  }
  struct Candidate {
    PlanarView* view;
    const Eigen::Isometry3d* pose;
  };
  std::vector<Candidate> views{{&keyframe_, &keyframe_pose_}};
  for (const DepthView& a : k.anchors) {
    PlanarView& v = anchors_[a.seq];
    if (v.surface.width != a.depth.width) {
      v.surface = makeDepthSurface(a.depth, a.camera, 1);
      v.planes_found = false;
    }
    views.push_back({&v, &a.pose});
  }
  // The hypothesis that puts the most of the frame's readings on a view's surface net of those
  // it puts in space that view saw empty: the same readings are checked against every view, so
  // the counts compare across views.
  const Candidate* best = nullptr;
  PlaneHypothesis best_hypothesis;
  int best_score = 0;
  for (const Candidate& v : views) {
    for (const PlaneHypothesis& h :
         registerPlanes(v.view->surface, planesOf(*v.view), frame, frame_planes, noise_)) {
      const int score = h.agreement.on - h.agreement.in_front;
      if (h.agreement.share() < vouch_share() || score <= best_score) continue;
      best = &v;
      best_hypothesis = h;
      best_score = score;
    }
  }
  if (!best) return std::nullopt;
  target_ = &best->view->surface;
  target_pose_ = *best->pose;
  relocalised_ = true;
  ++relocalised_total_;
  return S::from3D(target_pose_ * best_hypothesis.pose * c.mount.inverse());
}

template <class S>
std::vector<Statistic> DepthSlice<S>::statistics() const {
  return {{"frames", static_cast<double>(frames_)},
          {"alignment_s", time_s_},
          {"points_per_frame", perFrame(points_total_, frames_)},
          {"pairs_per_frame", perFrame(pairs_total_ + pairs_.size(), frames_)},
          {"relocalised", static_cast<double>(relocalised_total_)}};
}

template <class S>
void DepthKeyframeSlice<S>::integrate(const MergeContext<S>& context) {
  const Eigen::Isometry3d pose = S::to3D(context.pose) * raw.camera->mount;
  DepthKeyframe& k = scene.getOrInsert();
  if (!k.empty()) {
    if (!apart(k.pose, pose, distance(), angle())) return;
    keepAsAnchor(k, pose);
  }
  registration_.prepare(*raw.camera);
  subsampleDepth(registration_.apply(*raw.depth), raw.camera->intrinsics(), stride(), k.depth,
                 k.camera);
  k.camera.distortion = Distortion();  // registered depth is in the colour camera's ideal pinhole
  k.pose = pose;
  k.seq = context.seq;
}

template <class S>
void DepthKeyframeSlice<S>::keepAsAnchor(DepthKeyframe& k, const Eigen::Isometry3d& camera) const {
  if (anchors() == 0) return;
  for (const DepthView& a : k.anchors)
    if (!apart(a.pose, k.pose, anchor_distance(), anchor_angle())) return;
  DepthView anchor;
  subsampleDepth(k.depth, k.camera, anchor_stride(), anchor.depth, anchor.camera);
  anchor.pose = k.pose;
  anchor.seq = k.seq;
  k.anchors.push_back(std::move(anchor));
  if (k.anchors.size() <= static_cast<size_t>(anchors())) return;
  const auto far = std::max_element(
      k.anchors.begin(), k.anchors.end(), [&](const DepthView& a, const DepthView& b) {
        return (a.pose.translation() - camera.translation()).norm() <
               (b.pose.translation() - camera.translation()).norm();
      });
  k.anchors.erase(far);
}

template <class S>
void DepthKeyframeSlice<S>::handOver(const PropertyContainer& previous, PropertyContainer& next,
                                     const Pose& origin, uint64_t) {
  const DepthKeyframe* old = previous.find<DepthKeyframe>(scene.name());
  if (!old || old->empty()) return;
  DepthKeyframe& k = next.emplace<DepthKeyframe>(scene.name(), *old);
  const Eigen::Isometry3d to_next = S::to3D(origin).inverse();
  k.pose = to_next * old->pose;
  for (DepthView& a : k.anchors) a.pose = to_next * a.pose;
}

template struct DepthPointToPlane<Space2D>;
template struct DepthPointToPlane<Space3D>;
template class DepthSlice<Space2D>;
template class DepthSlice<Space3D>;
template class DepthKeyframeSlice<Space2D>;
template class DepthKeyframeSlice<Space3D>;

}  // namespace rgbd
}  // namespace plugslam
