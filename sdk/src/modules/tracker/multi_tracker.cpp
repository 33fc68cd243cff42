#include "plugslam/multi_tracker.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "plugslam/errors.h"
#include "plugslam/localizer.h"

namespace plugslam {
inline namespace abi_v1 {
namespace {

// "too few inliers (8 inliers of 30 factors: ...)", "degenerate information, weakest along
// (0.99, 0.12, 0.00)", ...: the debug log's reason for a failed frame.
template <class S>
std::string describeFailure(const AlignResult<S>& r) {
  std::string why;
  switch (r.failure) {
    case AlignFailure::none:
      why = "valid";
      break;
    case AlignFailure::no_data:
      why = "no data";
      break;
    case AlignFailure::too_few_inliers:
      why = "too few inliers";
      break;
    case AlignFailure::slid:
      why = "slid off the searched pose";
      break;
    case AlignFailure::degenerate: {
      why = "degenerate information, weakest along (";
      for (int i = 0; i < S::kDof; ++i) why += fmt::format("{}{:.2f}", i ? ", " : "", r.weakest(i));
      why += ")";
      break;
    }
  }
  return why + " (" + std::to_string(r.inliers) + " inliers of " + std::to_string(r.factors) +
         " factors" + (r.cues.empty() ? std::string() : ": " + describeCues(r.cues)) + ")";
}

}  // namespace

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
  // Without aligner slices no frame yields a factor: the tracker would "track" every frame at
  // the motion prediction. (Tracker slices are optional: an odometry prior alone needs no map.)
  if (!aligner)
    throw ParamError(
        "aligner", std::string("a tracker needs an aligner (sdk.MultiAligner") + S::kSuffix + ")");
  if (aligner->slices.empty())
    throw ParamError("aligner.slices",
                     std::string("the aligner has no slices, so no frame could be aligned: add "
                                 "one per cue (`plugslam plugins` lists the AlignerSlice") +
                         S::kSuffix + " types)");
  if (fallback_sigma().size() != static_cast<size_t>(S::kDof))
    throw ParamError("fallback_sigma", "expected " + std::to_string(S::kDof) + " values, got " +
                                           std::to_string(fallback_sigma().size()));
  for (double s : fallback_sigma())
    if (!(s > 0)) throw ParamError("fallback_sigma", "every value must be > 0");
}

template <class S>
ConstantVelocityBounds MultiTracker<S>::bounds() const {
  return constantVelocityBounds(max_acceleration(), max_angular_acceleration());
}

template <class S>
TrackEvents MultiTracker<S>::track(Frame& frame) {
  TrackEvents events;
  events.closed.swap(closed_);  // closed by reset() since the last frame
  ++stats_.frames;
  // Predict: the motion since the last frame, and how far off it may be.
  const Pose previous = pose_;
  const MotionEstimate<S> predicted = prediction_.predict(motion.get(), bounds(), frame);
  const Pose guess = S::normalized(previous * predicted.mean);
  if (!map_) {  // the first frame, or the first after a reset: it starts a map
    startLocalMap(frame, S::Matrix::Zero(), events);
    merge(frame);
    writeEstimate(frame, false);
    return events;
  }
  // Align: search the window the covariance sets, refine from the best pose.
  AlignResult<S> aligned = align(frame, map_->scene, Pose::Identity(), previous, guess, predicted);
  if (!aligned.valid && previous_map_ && align_previous_map() && !previous_map_->scene.empty()) {
    AlignResult<S> behind =
        align(frame, previous_map_->scene, origin_in_previous_, previous, guess, predicted);
    if (behind.valid) aligned = behind;
  }
  if (!aligned.valid && map_->scene.empty()) {
    // The map was started by a frame that brought no data: seed it again from this one.
    pose_ = guess;
    prediction_.solved(predicted.mean);
    merge(frame);
    writeEstimate(frame, false);
    return events;
  }
  // Without a valid solution the prediction is kept and a fresh local map starts from here, so
  // a bad stretch cannot corrupt the map built so far: the frame that failed against the map
  // does not enter it (its data would sit there at an unverified pose), it seeds the next one.
  const bool lost = !aligned.valid;
  pose_ = lost ? guess : aligned.pose;
  // A step the data fixed says how far the prediction was off; an ambiguous one or one the cues
  // could not vouch for may only repeat the prediction.
  prediction_.solved(S::normalized(previous.inverse() * pose_), aligned.fixesStep());
  count(frame, aligned);
  // Merge, then split.
  if (lost) {
    startLocalMap(frame, fallbackInformation(predicted.covariance), events);
  } else {
    merge(frame);
    if (splitter && splitter->split(splitQuery(frame, aligned))) {
      const std::shared_ptr<LocalMap> previous_map = map_;
      const Pose origin = pose_;
      startLocalMap(frame, aligned.H, events);
      seedAfterSplit(frame, *previous_map, origin);
    }
  }
  if (frames_in_map_ == 0) merge(frame);  // the frame seeds the new map
  writeEstimate(frame, lost, aligned.valid && aligned.unchecked);
  return events;
}

template <class S>
AlignResult<S> MultiTracker<S>::align(const Frame& frame, const PropertyContainer& scene,
                                      const Pose& to_scene, const Pose& previous, const Pose& guess,
                                      const MotionEstimate<S>& predicted) {
  // The solution's H and its rival are in the robot's tangent too: the change of scene frame
  // leaves them as they are.
  AlignResult<S> aligned =
      aligner->align(frame, scene,
                     prediction_.context(S::normalized(to_scene * previous),
                                         S::normalized(to_scene * guess), predicted));
  aligned.pose = S::normalized(to_scene.inverse() * aligned.pose);
  stats_.search_s += aligned.search_s;
  stats_.refine_s += aligned.refine_s;
  if (aligned.valid && aligned.searched) ++stats_.searched;
  if (spdlog::should_log(spdlog::level::trace)) {
    const Pose moved = S::normalized(guess.inverse() * aligned.pose);
    const typename S::Matrix& c = predicted.covariance;
    const typename S::Matrix& typical = prediction_.typical.value_or(c);
    spdlog::trace(
        "frame {}: sigma {:.3f} m {:.3f} rad (typical {:.3f} m {:.3f} rad); search {} score "
        "{:.3f}; {:.3f} m {:.3f} rad from the prediction; {} inliers of {}; {}",
        frame.seq, std::sqrt(c(0, 0)), std::sqrt(c(S::kDof - 1, S::kDof - 1)),
        std::sqrt(typical(0, 0)), std::sqrt(typical(S::kDof - 1, S::kDof - 1)),
        aligned.searched ? "found" : "none", aligned.search_score, S::distance(moved),
        S::angle(moved), aligned.inliers, aligned.factors, toString(aligned.failure));
  }
  if (aligned.valid && aligned.ambiguous) {
    ++stats_.ambiguous;
    spdlog::debug(
        "frame {}: ambiguous match (score {:.3f}): a rival pose {:.3f} m, {:.3f} rad "
        "away scores nearly as well; the prediction chose",
        frame.seq, aligned.search_score, aligned.rival.template head<S::kDim>().norm(),
        aligned.rival.template tail<S::kDof - S::kDim>().norm());
  }
  return aligned;
}

template <class S>
void MultiTracker<S>::count(const Frame& frame, const AlignResult<S>& aligned) {
  if (aligned.valid) {
    ++stats_.aligned;
    stats_.inlier_ratio_sum += aligned.inlierRatio();
    if (aligned.hypothesis) {
      ++stats_.hypotheses;
      spdlog::debug("frame {}: placed by a hypothesis other than the prediction", frame.seq);
    }
    if (aligned.unchecked) {
      // Never silent: a pose the cues could not vouch for is said, and listed in the report.
      ++stats_.unchecked;
      if (stats_.unchecked_frames.size() < TrackerStats::kMaxListed)
        stats_.unchecked_frames.push_back(frame.seq);
      const auto level = stats_.unchecked <= 10 ? spdlog::level::warn : spdlog::level::debug;
      spdlog::log(level,
                  "frame {}: the pose could not be checked (the cues barely measure the motion "
                  "and no hypothesis without the prediction was found); it may be wrong",
                  frame.seq);
    }
  } else {
    stats_.countFailure(aligned.failure);
    spdlog::debug("frame {}: alignment failed: {}; new local map", frame.seq,
                  describeFailure(aligned));
  }
}

template <class S>
SplitQuery MultiTracker<S>::splitQuery(const Frame& frame, const AlignResult<S>& aligned) const {
  SplitQuery q;
  q.distance = S::distance(pose_);
  q.angle = S::angle(pose_);
  q.elapsed = frame.stamp - map_->first_stamp;
  q.inlier_ratio = aligned.inlierRatio();
  q.frames = frames_in_map_;
  return q;
}

template <class S>
typename S::Matrix MultiTracker<S>::fallbackInformation(
    const typename S::Matrix& prediction) const {
  // The kept prediction is as uncertain as its covariance says, and no surer than fallback_sigma.
  typename S::Matrix covariance = prediction;
  for (int i = 0; i < S::kDof; ++i) covariance(i, i) += fallback_sigma()[i] * fallback_sigma()[i];
  return covariance.inverse();
}

template <class S>
void MultiTracker<S>::merge(const Frame& frame) {
  const auto start = std::chrono::steady_clock::now();
  for (auto& slice : slices) slice->merge(frame, map_->scene, pose_);
  // A slice that refined the frame's pose with what its map knows (a bundle adjustment) gives
  // the frame's estimate, and where the next prediction starts.
  for (auto& slice : slices)
    if (const auto* r = dynamic_cast<const RefiningSlice<S>*>(slice.get()))
      if (const std::optional<Pose> refined = r->refinedPose()) pose_ = *refined;
  stats_.merge_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ++frames_in_map_;
  map_->last_seq = frame.seq;
  map_->last_stamp = frame.stamp;
}

template <class S>
void MultiTracker<S>::seedAfterSplit(const Frame& frame, const LocalMap& previous,
                                     const Pose& origin) {
  if (!hand_over()) return;  // merge() seeds it from the frame alone
  for (auto& slice : slices) {
    if (auto* carrier = dynamic_cast<HandoverSlice<S>*>(slice.get()))
      carrier->handOver(previous.scene, map_->scene, origin, frame.seq);
    else
      slice->merge(frame, map_->scene, pose_);
  }
  ++frames_in_map_;
  map_->last_seq = frame.seq;
  map_->last_stamp = frame.stamp;
}

template <class S>
void MultiTracker<S>::writeEstimate(Frame& frame, bool lost, bool unchecked) const {
  frame.estimate.valid = true;
  frame.estimate.local_map = map_->id;
  frame.estimate.in_map = S::to3D(pose_);
  frame.estimate.frozen = false;  // the back-end may still move this map
  frame.estimate.lost = lost;
  frame.estimate.unchecked = unchecked;
}

template <class S>
void MultiTracker<S>::startLocalMap(const Frame& frame, const typename S::Matrix& information,
                                    TrackEvents& events) {
  auto next = std::make_shared<LocalMap>();
  next->id = next_id_++;
  next->dimension = S::kDim;
  next->first_seq = next->last_seq = frame.seq;
  next->first_stamp = next->last_stamp = frame.stamp;
  previous_map_ = map_;
  origin_in_previous_ = pose_;
  if (map_) {
    // The new map's frame is the robot's pose now; the edge from the old map is that pose.
    next->previous = map_->id;
    next->relative = S::to3D(pose_);
    next->information = information;
    events.closed.push_back(map_);
  }
  map_ = next;
  events.started = next;
  pose_ = Pose::Identity();
  frames_in_map_ = 0;
  ++stats_.local_maps;
}

template <class S>
void MultiTracker<S>::reset() {
  // The current map is handed over as closed, so the back-end still looks for loops from it.
  if (map_) closed_.push_back(map_);
  map_.reset();
  previous_map_.reset();
  pose_ = Pose::Identity();
  prediction_.reset();
  frames_in_map_ = 0;
  if (motion) motion->reset();
}

template <class S>
void MultiTracker<S>::continueSession(int64_t next_id) {
  if (map_) throw InputError("a session can only be restored before the first frame");
  if (next_id < 0) throw InputError("next local map id must be >= 0");
  next_id_ = next_id;
}

template <class S>
std::shared_ptr<Tracker> MultiTracker<S>::localizer(
    std::vector<std::shared_ptr<const LocalMap>> maps) const {
  // Also mid-run (localization from an unknown start hands over once it locked on): the
  // localizer shares the aligner and the motion model, whose readings go on.
  return Localizer<S>::create(name(), aligner.shared(), motion.shared(), bounds(), localize_tie(),
                              std::move(maps));
}

template class MultiTracker<Space2D>;
template class MultiTracker<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
