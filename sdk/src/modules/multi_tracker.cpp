#include "plugslam/multi_tracker.h"

#include <spdlog/spdlog.h>

#include <limits>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

Tracker::~Tracker() = default;

void Tracker::continueSession(int64_t) {
  throw InputError("tracker '" + name() + "' (" + typeName() + ") cannot extend a saved session");
}

void Tracker::localizeIn(std::vector<std::shared_ptr<const LocalMap>>) {
  throw InputError("tracker '" + name() + "' (" + typeName() + ") cannot localize in saved maps");
}
Splitter::~Splitter() = default;
template <class S>
TrackerSlice<S>::~TrackerSlice() = default;
template <class S>
MotionModel<S>::~MotionModel() = default;

bool DistanceSplitter::split(const SplitQuery& q) const {
  return (distance() > 0 && q.distance >= distance()) || (angle() > 0 && q.angle >= angle()) ||
         (time() > 0 && q.elapsed >= time()) ||
         (min_inlier_ratio() > 0 && q.inlier_ratio < min_inlier_ratio());
}

template <class S>
MultiTracker<S>::MultiTracker() {
  addAction("reset", "close the current local map and start over from the next frame",
            [this](const std::vector<std::string>&) {
              reset();
              return std::string("tracker reset; the next frame starts local map ") +
                     std::to_string(next_id_);
            });
}
template <class S>
MultiTracker<S>::~MultiTracker() = default;

template <class S>
void MultiTracker<S>::configure() {
  if (fallback_sigma().size() != static_cast<size_t>(S::kDof))
    throw ParamError("fallback_sigma", "expected " + std::to_string(S::kDof) + " values, got " +
                                           std::to_string(fallback_sigma().size()));
  for (double s : fallback_sigma())
    if (!(s > 0)) throw ParamError("fallback_sigma", "every value must be > 0");
}

template <class S>
void MultiTracker<S>::reset() {
  // The current map is handed over as closed, so the back-end still looks for loops from it.
  if (map_) closed_.push_back(map_);
  map_.reset();
  located_.reset();
  pose_ = last_motion_ = Pose::Identity();
  frames_in_map_ = 0;
  if (motion) motion->reset();
}

template <class S>
void MultiTracker<S>::continueSession(int64_t next_id) {
  if (map_ || !frozen_.empty())
    throw InputError("a session can only be restored before the first frame");
  if (next_id < 0) throw InputError("next local map id must be >= 0");
  next_id_ = next_id;
}

template <class S>
void MultiTracker<S>::localizeIn(std::vector<std::shared_ptr<const LocalMap>> maps) {
  if (map_) throw InputError("localization can only start before the first frame");
  if (maps.empty()) throw InputError("localization needs at least one saved local map");
  for (const auto& m : maps)
    if (!m || m->dimension != S::kDim)
      throw InputError("localization: a saved map is not " + std::to_string(S::kDim) + "D");
  frozen_ = std::move(maps);
  located_.reset();
}

template <class S>
void MultiTracker<S>::trackFrozen(Frame& frame) {
  // Localization: the nearest frozen map (by origin, in the world) is the scene to align with;
  // the pose is re-expressed when the robot moves on to another map. Nothing is merged or split.
  ++stats_.frames;
  const Eigen::Isometry3d at = located_ ? located_->origin : Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d previous_world = at * S::to3D(pose_);
  const Eigen::Isometry3d guess_world = at * S::to3D(predict(frame));
  std::shared_ptr<const LocalMap> best;
  double best_d = std::numeric_limits<double>::infinity();
  for (const auto& m : frozen_) {
    const double d = (m->origin.translation() - guess_world.translation()).norm();
    if (d < best_d) {
      best_d = d;
      best = m;
    }
  }
  located_ = best;
  const Eigen::Isometry3d to_map = best->origin.inverse();
  const Pose previous = S::normalized(S::from3D(to_map * previous_world));
  const Pose guess = S::normalized(S::from3D(to_map * guess_world));
  AlignResult<S> aligned = aligner->align(frame, best->scene, AlignContext<S>{previous, guess});
  if (aligned.valid) {
    pose_ = aligned.pose;
    ++stats_.aligned;
    stats_.inlier_ratio_sum += aligned.inlierRatio();
  } else {
    pose_ = guess;
    ++stats_.failed;
  }
  last_motion_ = S::normalized(previous.inverse() * pose_);
  frame.estimate.valid = true;
  frame.estimate.local_map = best->id;
  frame.estimate.in_map = S::to3D(pose_);
  frame.estimate.world = best->origin * frame.estimate.in_map;
}

template <class S>
void MultiTracker<S>::track(Frame& frame) {
  if (!frozen_.empty()) return trackFrozen(frame);
  ++stats_.frames;
  const Pose previous = pose_;
  const Pose guess = predict(frame);
  typename S::Matrix information = S::Matrix::Zero();
  bool lost = false;
  if (!map_) {
    startLocalMap(frame, information);
  } else {
    AlignResult<S> aligned = aligner->align(frame, map_->scene, AlignContext<S>{previous, guess});
    if (!aligned.valid && map_->scene.empty()) {
      // The map was started by a frame that brought no data: seed it again from this one.
      pose_ = guess;
      last_motion_ = S::normalized(previous.inverse() * pose_);
      merge(frame);
      writeEstimate(frame);
      return;
    }
    if (aligned.valid) {
      pose_ = aligned.pose;
      information = aligned.H;
      ++stats_.aligned;
      stats_.inlier_ratio_sum += aligned.inlierRatio();
    } else {
      // No valid solution: trust the prediction and start a fresh local map from here, so a
      // bad stretch cannot corrupt the map built so far.
      pose_ = guess;
      lost = true;
      ++stats_.failed;
      spdlog::debug("frame {}: alignment failed ({} inliers of {} factors); new local map",
                    frame.seq, aligned.inliers, aligned.factors);
    }
    last_motion_ = S::normalized(previous.inverse() * pose_);
    merge(frame);
    SplitQuery q;
    q.distance = S::distance(pose_);
    q.angle = S::angle(pose_);
    q.elapsed = frame.stamp - map_->first_stamp;
    q.inlier_ratio = aligned.inlierRatio();
    q.frames = frames_in_map_;
    if (lost || (splitter && splitter->split(q))) {
      if (lost) {
        information.setZero();
        for (int i = 0; i < S::kDof; ++i)
          information(i, i) = 1.0 / (fallback_sigma()[i] * fallback_sigma()[i]);
      }
      startLocalMap(frame, information);
    }
  }
  if (frames_in_map_ == 0) merge(frame);
  writeEstimate(frame);
}

template <class S>
void MultiTracker<S>::writeEstimate(Frame& frame) const {
  frame.estimate.valid = true;
  frame.estimate.local_map = map_->id;
  frame.estimate.in_map = S::to3D(pose_);
  frame.estimate.world = map_->origin * frame.estimate.in_map;
}

template <class S>
typename S::Pose MultiTracker<S>::predict(const Frame& frame) {
  std::optional<Pose> delta;
  if (motion) delta = motion->predict(frame);
  if (!delta) delta = constant_velocity() ? last_motion_ : Pose::Identity();
  return S::normalized(pose_ * *delta);
}

template <class S>
void MultiTracker<S>::merge(const Frame& frame) {
  for (auto& slice : slices) slice->merge(frame, map_->scene, pose_);
  ++frames_in_map_;
  map_->last_seq = frame.seq;
  map_->last_stamp = frame.stamp;
}

template <class S>
void MultiTracker<S>::startLocalMap(const Frame& frame, const typename S::Matrix& information) {
  auto next = std::make_shared<LocalMap>();
  next->id = next_id_++;
  next->dimension = S::kDim;
  next->first_seq = next->last_seq = frame.seq;
  next->first_stamp = next->last_stamp = frame.stamp;
  if (map_) {
    // The new map's frame is the robot's pose now; the edge from the old map is that pose.
    next->previous = map_->id;
    next->relative = S::to3D(pose_);
    next->origin = map_->origin * next->relative;
    next->information = information;
    closed_.push_back(map_);
  }
  map_ = next;
  pose_ = Pose::Identity();
  frames_in_map_ = 0;
  ++stats_.local_maps;
}

template <class S>
std::vector<std::shared_ptr<LocalMap>> MultiTracker<S>::takeClosed() {
  std::vector<std::shared_ptr<LocalMap>> out;
  out.swap(closed_);
  return out;
}

template <class S>
void MultiTracker<S>::setCurrentOrigin(const Eigen::Isometry3d& origin) {
  if (map_) map_->origin = origin;
}

template class TrackerSlice<Space2D>;
template class TrackerSlice<Space3D>;
template class MotionModel<Space2D>;
template class MotionModel<Space3D>;
template class MultiTracker<Space2D>;
template class MultiTracker<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
