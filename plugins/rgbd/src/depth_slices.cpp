#include "depth_slices.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace plugslam {
namespace rgbd {

void save(OutArchive& ar, const DepthKeyframe& k) {
  ar.beginObject();
  ar.field("depth", k.depth);
  ar.field("camera", k.camera);
  ar.field("pose", k.pose);
  ar.field("seq", k.seq);
  ar.endObject();
}

void load(InArchive& ar, DepthKeyframe& k) {
  ar.beginObject();
  ar.field("depth", k.depth);
  ar.field("camera", k.camera);
  ar.field("pose", k.pose);
  ar.field("seq", k.seq);
  ar.endObject();
  if (!k.empty() && (k.camera.width != k.depth.width || k.camera.height != k.depth.height))
    ar.fail("depth keyframe: the camera's size differs from the depth image's");
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
  if (scene->empty()) return false;
  Stopwatch watch(time_s_);
  const DepthKeyframe& k = *scene;
  // The keyframe's surface is built once per keyframe (it changes when the tracker slice takes
  // a new one or the map is a new one).
  if (k.seq != keyframe_seq_ || !k.pose.isApprox(keyframe_pose_) ||
      keyframe_.width != k.depth.width) {
    keyframe_ = makeDepthSurface(k.depth, k.camera, 1);
    keyframe_seq_ = k.seq;
    keyframe_pose_ = k.pose;
  }
  registration_.prepare(*raw.camera);
  const DepthImage& d = registration_.apply(*raw.depth);
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
  if (!scene.bound() || keyframe_.width == 0 || round_++ < first_round()) return;
  Stopwatch watch(time_s_);
  // Checked at every round's estimate, so a recovered pose near the keyframe gets the cue.
  const Eigen::Isometry3d to_keyframe = keyframe_pose_.inverse() * S::to3D(t);
  if ((to_keyframe * raw.camera->mount).translation().norm() > keyframe_distance()) return;
  const double gate = max_distance();
  std::vector<double> residuals;  // point-to-plane, at t
  for (size_t i = 0; i < points_.size(); ++i) {
    const Eigen::Vector3d x = to_keyframe * points_[i];
    const long j = projectOnto(keyframe_, x);
    if (j < 0) continue;
    const Eigen::Vector3f& n = keyframe_.normals[static_cast<size_t>(j)];
    const Eigen::Vector3d q = keyframe_.points[static_cast<size_t>(j)].cast<double>();
    const double sq = noise_.sigma(q.z());
    const double sigma = std::sqrt(sigmas_[i] * sigmas_[i] + sq * sq);
    // Far readings are noisier (2.6 cm at 4 m for a Kinect): the gate widens by three of the
    // pair's sigmas, or the far wall, the one surface that fixes the depth axis, drops out.
    if ((x - q).norm() > gate + 3.0 * sigma) continue;
    pairs_.push_back(Pair{static_cast<int>(i), keyframe_pose_ * q,
                          keyframe_pose_.linear() * n.cast<double>(), sigma});
    residuals.push_back(n.cast<double>().dot(x - q));
  }
  // Judged at each association's pose: the last one is the solution's.
  vouched_ = pinnedDirections(t, residuals);
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
int DepthSlice<S>::pinnedDirections(const Pose& t, const std::vector<double>& residuals) const {
  // The readings on the keyframe's surface, within the kernel's width: only they can vouch.
  std::vector<size_t> on;
  for (size_t k = 0; k < pairs_.size(); ++k)
    if (std::abs(residuals[k]) <= kernel_scale() * pairs_[k].sigma) on.push_back(k);
  if (on.empty() ||
      static_cast<double>(on.size()) < vouch_share() * static_cast<double>(points_.size()))
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
std::vector<Statistic> DepthSlice<S>::statistics() const {
  return {{"frames", static_cast<double>(frames_)},
          {"alignment_s", time_s_},
          {"points_per_frame", perFrame(points_total_, frames_)},
          {"pairs_per_frame", perFrame(pairs_total_ + pairs_.size(), frames_)}};
}

template <class S>
void DepthKeyframeSlice<S>::integrate(const MergeContext<S>& context) {
  const Eigen::Isometry3d pose = S::to3D(context.pose) * raw.camera->mount;
  DepthKeyframe& k = scene.getOrInsert();
  if (!k.empty()) {
    const Eigen::Isometry3d moved = k.pose.inverse() * pose;
    if (moved.translation().norm() < distance() &&
        Eigen::AngleAxisd(moved.linear()).angle() < angle())
      return;
  }
  registration_.prepare(*raw.camera);
  subsampleDepth(registration_.apply(*raw.depth), raw.camera->intrinsics(), stride(), k.depth,
                 k.camera);
  k.camera.distortion = Distortion();  // registered depth is in the colour camera's ideal pinhole
  k.pose = pose;
  k.seq = context.seq;
}

template <class S>
void DepthKeyframeSlice<S>::handOver(const PropertyContainer& previous, PropertyContainer& next,
                                     const Pose& origin, uint64_t) {
  const DepthKeyframe* old = previous.find<DepthKeyframe>(scene.name());
  if (!old || old->empty()) return;
  DepthKeyframe& k = next.emplace<DepthKeyframe>(scene.name(), *old);
  k.pose = S::to3D(origin).inverse() * old->pose;
}

template struct DepthPointToPlane<Space2D>;
template struct DepthPointToPlane<Space3D>;
template class DepthSlice<Space2D>;
template class DepthSlice<Space3D>;
template class DepthKeyframeSlice<Space2D>;
template class DepthKeyframeSlice<Space3D>;

}  // namespace rgbd
}  // namespace plugslam
