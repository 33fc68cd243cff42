#include "plugslam/multi_tracker.h"

#include <spdlog/spdlog.h>

#include <algorithm>
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
void TrackerSlice<S>::merge(const Frame& frame, PropertyContainer& scene, const Pose& t) {
  bool present = true;
  for (EntryBase* entry : entries()) {
    if (entry->writes()) {
      if (entry->container() != Container::scene)
        throw InputError("tracker slice '" + name() + "': '" + entry->key() + "' " +
                         entry->describe() + "; a tracker slice writes scene entries only");
      entry->bind(&scene);
      continue;
    }
    const Container c = entry->container();
    entry->bind(static_cast<const PropertyContainer*>(
        c == Container::scene ? &scene : c == Container::raw ? &frame.raw : &frame.measurement));
    present = present && entry->bound();
  }
  if (present) integrate(MergeContext<S>{t, frame.seq, frame.stamp});
}
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
  if (!max_correction().empty() && max_correction().size() != 2)
    throw ParamError("max_correction",
                     "expected 2 values (translation m, rotation rad) or an empty list, got " +
                         std::to_string(max_correction().size()));
  for (double v : max_correction())
    if (!(v > 0)) throw ParamError("max_correction", "every value must be > 0");
}

template <class S>
void MultiTracker<S>::reset() {
  // The current map is handed over as closed, so the back-end still looks for loops from it.
  if (map_) closed_.push_back(map_);
  map_.reset();
  located_.reset();
  pose_ = last_motion_ = Pose::Identity();
  frames_in_map_ = 0;
  model_motion_.reset();
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
  // Localization: the frame is aligned against the map it is in and the maps whose origins are
  // nearest its predicted world pose; the valid alignment explaining most of the frame wins (maps
  // of different passes need not agree where the mapping run closed no loop). Alignments within
  // localize_tie of the best inlier ratio are equally good (most are at 1.0), and the one closest
  // to the prediction wins among them: a map that also admits a turned solution (built while the
  // robot turned, a corridor) must not win for being tried first. The pose is kept in the winning
  // map's frame. Nothing is merged or split.
  constexpr size_t kNearest = 3;
  ++stats_.frames;
  const Eigen::Isometry3d at = located_ ? located_->origin : Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d previous_world = at * S::to3D(pose_);
  const Eigen::Isometry3d guess_world = at * S::to3D(predict(frame));
  std::vector<std::pair<double, std::shared_ptr<const LocalMap>>> near;
  for (const auto& m : frozen_)
    if (m != located_)
      near.emplace_back((m->origin.translation() - guess_world.translation()).norm(), m);
  const size_t k = std::min(kNearest, near.size());
  std::partial_sort(near.begin(), near.begin() + k, near.end(),
                    [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::shared_ptr<const LocalMap>> candidates;
  if (located_) candidates.push_back(located_);
  for (size_t i = 0; i < k; ++i) candidates.push_back(near[i].second);
  std::shared_ptr<const LocalMap> best;
  AlignResult<S> best_result;
  Pose best_previous = Pose::Identity(), fallback_guess = Pose::Identity();
  std::shared_ptr<const LocalMap> fallback = k > 0 ? near[0].second : located_;
  struct Tried {
    std::shared_ptr<const LocalMap> map;
    AlignResult<S> result;
    Pose previous;
    double correction;  // translation [m] + rotation [rad] from the prediction
  };
  std::vector<Tried> valid;
  double best_ratio = 0;
  for (const auto& m : candidates) {
    const Eigen::Isometry3d to_map = m->origin.inverse();
    const Pose previous = S::normalized(S::from3D(to_map * previous_world));
    const Pose guess = S::normalized(S::from3D(to_map * guess_world));
    if (m == fallback) fallback_guess = guess;
    AlignResult<S> r =
        aligner->align(frame, m->scene, alignContext(previous, guess));
    if (!r.valid) continue;
    const Pose correction = S::normalized(guess.inverse() * r.pose);
    best_ratio = std::max(best_ratio, r.inlierRatio());
    valid.push_back({m, r, previous, S::distance(correction) + S::angle(correction)});
  }
  const Tried* chosen = nullptr;
  for (const auto& t : valid)
    if (t.result.inlierRatio() >= best_ratio - localize_tie() &&
        (!chosen || t.correction < chosen->correction))
      chosen = &t;
  if (chosen) {
    best = chosen->map;
    best_result = chosen->result;
    best_previous = chosen->previous;
  }
  if (best) {
    located_ = best;
    pose_ = best_result.pose;
    ++stats_.aligned;
    stats_.inlier_ratio_sum += best_result.inlierRatio();
    last_motion_ = S::normalized(best_previous.inverse() * pose_);
  } else {
    const Eigen::Isometry3d to_map = fallback->origin.inverse();
    const Pose previous = S::normalized(S::from3D(to_map * previous_world));
    located_ = fallback;
    pose_ = fallback_guess;
    last_motion_ = S::normalized(previous.inverse() * pose_);
    ++stats_.failed;
    spdlog::debug("frame {}: localization failed in maps near {}", frame.seq, fallback->id);
  }
  frame.estimate.valid = true;
  frame.estimate.local_map = located_->id;
  frame.estimate.in_map = S::to3D(pose_);
  frame.estimate.world = located_->origin * frame.estimate.in_map;
  frame.estimate.frozen = true;
  frame.estimate.lost = best == nullptr;
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
    AlignResult<S> aligned =
        aligner->align(frame, map_->scene, alignContext(previous, guess));
    if (!aligned.valid && map_->scene.empty()) {
      // The map was started by a frame that brought no data: seed it again from this one.
      pose_ = guess;
      last_motion_ = S::normalized(previous.inverse() * pose_);
      merge(frame);
      writeEstimate(frame, false);
      return;
    }
    if (aligned.valid && model_motion_ && !max_correction().empty()) {
      const Pose correction = S::normalized(guess.inverse() * aligned.pose);
      if (S::distance(correction) > max_correction()[0] ||
          S::angle(correction) > max_correction()[1]) {
        spdlog::debug("frame {}: alignment moved the prediction by {:.3f} m, {:.3f} rad; rejected",
                      frame.seq, S::distance(correction), S::angle(correction));
        aligned.valid = false;
      }
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
      spdlog::debug("frame {}: alignment failed ({} inliers of {} factors: {}); new local map",
                    frame.seq, aligned.inliers, aligned.factors, describeCues(aligned.cues));
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
  writeEstimate(frame, lost);
}

template <class S>
void MultiTracker<S>::writeEstimate(Frame& frame, bool lost) const {
  frame.estimate.valid = true;
  frame.estimate.local_map = map_->id;
  frame.estimate.in_map = S::to3D(pose_);
  frame.estimate.world = map_->origin * frame.estimate.in_map;
  frame.estimate.frozen = false;  // the back-end may still move this map
  frame.estimate.lost = lost;
}

template <class S>
typename S::Pose MultiTracker<S>::predict(const Frame& frame) {
  model_motion_.reset();
  model_motion_entry_.clear();
  if (motion) {
    model_motion_ = motion->predict(frame);
    // Named only when the model reads one raw entry, so a slice can tell it read the same.
    int raw_inputs = 0;
    for (const EntryBase* e : motion->entries())
      if (!e->writes() && e->container() == Container::raw) {
        ++raw_inputs;
        model_motion_entry_ = e->name();
      }
    if (raw_inputs != 1) model_motion_entry_.clear();
  }
  const Pose delta =
      model_motion_ ? *model_motion_ : constant_velocity() ? last_motion_ : Pose::Identity();
  return S::normalized(pose_ * delta);
}

template <class S>
AlignContext<S> MultiTracker<S>::alignContext(const Pose& previous, const Pose& guess) const {
  AlignContext<S> context{previous, guess, model_motion_};
  if (model_motion_) context.motion_entry = model_motion_entry_;
  return context;
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
