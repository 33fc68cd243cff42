#include "plugslam/multi_tracker.h"

#include <algorithm>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

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
    case AlignFailure::none: why = "valid"; break;
    case AlignFailure::no_data: why = "no data"; break;
    case AlignFailure::too_few_inliers: why = "too few inliers"; break;
    case AlignFailure::gate: why = "correction gate"; break;
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
    throw ParamError("aligner", std::string("a tracker needs an aligner (sdk.MultiAligner") +
                                    S::kSuffix + ")");
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
  if (!max_correction().empty() && max_correction().size() != 2)
    throw ParamError("max_correction",
                     "expected 2 values (translation m, rotation rad) or an empty list, got " +
                         std::to_string(max_correction().size()));
  for (double v : max_correction())
    if (!(v > 0)) throw ParamError("max_correction", "every value must be > 0");
  if (!max_correction_per_motion().empty()) {
    if (max_correction_per_motion().size() != 4)
      throw ParamError("max_correction_per_motion",
                       "expected 4 values (translation per m and per rad, rotation per m and per "
                       "rad) or an empty list, got " +
                           std::to_string(max_correction_per_motion().size()));
    if (max_correction().empty())
      throw ParamError("max_correction_per_motion",
                       "grows the max_correction gate, so max_correction must be set too");
  }
  for (double v : max_correction_per_motion())
    if (!(v >= 0)) throw ParamError("max_correction_per_motion", "every value must be >= 0");
}

template <class S>
TrackEvents MultiTracker<S>::track(Frame& frame) {
  TrackEvents events;
  events.closed.swap(closed_);  // closed by reset() since the last frame
  ++stats_.frames;
  const Pose previous = pose_;
  const Pose guess = prediction_.predict(motion.get(), constant_velocity(), frame, pose_);
  if (!map_) {  // the first frame, or the first after a reset: it starts a map
    startLocalMap(frame, S::Matrix::Zero(), events);
    merge(frame);
    writeEstimate(frame, false);
    return events;
  }
  AlignResult<S> aligned = align(frame, map_->scene, Pose::Identity(), previous, guess);
  if (!aligned.valid && previous_map_ && align_previous_map() && !previous_map_->scene.empty()) {
    AlignResult<S> behind =
        align(frame, previous_map_->scene, origin_in_previous_, previous, guess);
    if (behind.valid) {
      spdlog::debug("frame {}: aligned in the previous local map {} ({} inliers)", frame.seq,
                    previous_map_->id, behind.inliers);
      aligned = behind;
    }
  }
  if (!aligned.valid && map_->scene.empty()) {
    // The map was started by a frame that brought no data: seed it again from this one.
    pose_ = guess;
    prediction_.last_motion = S::normalized(previous.inverse() * pose_);
    merge(frame);
    writeEstimate(frame, false);
    return events;
  }
  // Without a valid solution the prediction is kept and a fresh local map starts from here, so
  // a bad stretch cannot corrupt the map built so far: the frame that failed against the map
  // does not enter it (its data would sit there at an unverified pose), it seeds the next one.
  const bool lost = !aligned.valid;
  pose_ = lost ? guess : aligned.pose;
  prediction_.last_motion = S::normalized(previous.inverse() * pose_);
  motion_residual_.reset();
  if (!lost && prediction_.model_motion) {
    motion_residual_ = S::normalized(prediction_.model_motion->inverse() * prediction_.last_motion);
    if (auto* model = dynamic_cast<CalibratingMotionModel<S>*>(motion.get()))
      model->solved(prediction_.last_motion);
  }
  count(frame, aligned);
  if (lost) {
    startLocalMap(frame, fallbackInformation(), events);
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
  writeEstimate(frame, lost);
  return events;
}

template <class S>
AlignResult<S> MultiTracker<S>::align(const Frame& frame, const PropertyContainer& scene,
                                      const Pose& to_scene, const Pose& previous,
                                      const Pose& guess) {
  AlignContext<S> context{S::normalized(to_scene * previous), S::normalized(to_scene * guess),
                          prediction_.model_motion, prediction_.model_entry};
  context.motion_residual = motion_residual_;
  context.motion_extrapolated = prediction_.model_extrapolated;
  AlignResult<S> aligned = aligner->align(frame, scene, context);
  const std::optional<std::pair<double, double>> gate = correctionGate();
  if (aligned.valid && !aligned.seeded && !context.motionMeasuredInFull() && aligner->seeder)
    aligned = checkUnmeasured(frame, scene, context, gate, std::move(aligned));
  // The tangent is the robot's own (boxplus multiplies on the right), so H needs no change.
  aligned.pose = S::normalized(to_scene.inverse() * aligned.pose);
  if (!gate) {  // nothing bounds the correction: every valid solve counts, seeded or not
    if (aligned.valid && aligned.seeded) ++stats_.recovered;
    return aligned;
  }
  const auto beyond = [&](const Pose& pose) { return beyondGate(*gate, guess, pose); };
  // Whether a seeded solve beats the one from the prediction that explained `against` inliers.
  const auto seedCounts = [&](const AlignResult<S>& seeded, size_t against) {
    if (!beyond(seeded.pose)) return seeded.inliers > against;
    return seed_beyond_gate() > 0 &&
           static_cast<double>(seeded.inliers) >= seed_beyond_gate() * static_cast<double>(against);
  };
  const auto describe = [&](const char* what, const Pose& pose) {
    const Pose moved = S::normalized(guess.inverse() * pose);
    return fmt::format("{} {:.3f} m, {:.3f} rad from the prediction (gate {:.3f} m, {:.3f} rad)",
                       what, S::distance(moved), S::angle(moved), gate->first, gate->second);
  };
  if (aligned.valid && aligned.seeded) {
    // The solve from the prediction failed and the seeder's search found a pose.
    if (!seedCounts(aligned, aligned.unseeded_inliers)) {
      spdlog::debug("frame {}: {}, {} inliers against the failed solve's {}: rejected", frame.seq,
                    describe("the seeder's pose is", aligned.pose), aligned.inliers,
                    aligned.unseeded_inliers);
      aligned.valid = false;
      aligned.failure = AlignFailure::gate;
    }
  } else if (aligned.valid && beyond(aligned.pose)) {
    // Either the prediction is poor (slip, bad odometry) or the solve slid (a corridor): the
    // seeder's search around the prediction decides; without one the prediction is kept. A seed
    // elsewhere must explain more than the solve it replaces, else the frame fails.
    AlignResult<S> recovered = aligner->recover(frame, scene, context);
    if (recovered.valid) recovered.pose = S::normalized(to_scene.inverse() * recovered.pose);
    // The search is unambiguous over its whole window, so a seed whose solve ends where the
    // solve from the prediction did confirms it: the prediction was poor, not the solve.
    const Pose apart = S::normalized(aligned.pose.inverse() * recovered.pose);
    const bool confirms = recovered.valid &&
                          S::distance(apart) <= aligner->seed_tolerance()[0] &&
                          S::angle(apart) <= aligner->seed_tolerance()[1];
    if (recovered.valid && (confirms || seedCounts(recovered, aligned.inliers))) {
      spdlog::debug("frame {}: {}; {} ({} inliers against {})", frame.seq,
                    describe("alignment", aligned.pose),
                    describe("the seeder's search puts it", recovered.pose), recovered.inliers,
                    aligned.inliers);
      aligned = recovered;
    } else {
      spdlog::debug("frame {}: {}; rejected{}", frame.seq, describe("alignment", aligned.pose),
                    recovered.valid ? fmt::format(" ({}, {} inliers against {})",
                                                  describe("the seeder's pose", recovered.pose),
                                                  recovered.inliers, aligned.inliers)
                                    : std::string());
      aligned.valid = false;
      aligned.failure = AlignFailure::gate;
    }
  }
  if (aligned.valid && aligned.seeded) ++stats_.recovered;
  return aligned;
}

template <class S>
AlignResult<S> MultiTracker<S>::checkUnmeasured(
    const Frame& frame, const PropertyContainer& scene, const AlignContext<S>& context,
    const std::optional<std::pair<double, double>>& gate, AlignResult<S> aligned) {
  // Without a measured motion the prediction is the last step again, off by a whole step when
  // the robot stopped, started or turned the other way, and the solve converges to whatever
  // minimum lies nearest it, with every pair an inlier: no count or gate tells it from the right
  // one. The seeder's search covers the step's reach; where it is unambiguous and its solve
  // explains more of the scan elsewhere, it wins (issue 20: laser only). The same holds for the
  // part of a motion the model extrapolated (odometry read less often than the scans), within
  // the gate, which has grown by that part.
  AlignResult<S> searched = aligner->recover(frame, scene, context);
  if (!searched.valid || searched.inliers <= aligned.inliers) return aligned;
  if (gate && beyondGate(*gate, context.guess, searched.pose)) return aligned;
  const Pose apart = S::normalized(aligned.pose.inverse() * searched.pose);
  if (S::distance(apart) <= aligner->seed_tolerance()[0] &&
      S::angle(apart) <= aligner->seed_tolerance()[1])
    return aligned;  // the same minimum
  spdlog::debug("frame {}: with unmeasured motion the solve landed {:.3f} m, {:.3f} rad from "
                "the seeder's, which explains more of the scan ({} inliers against {}): taken",
                frame.seq, S::distance(apart), S::angle(apart), searched.inliers,
                aligned.inliers);
  return searched;
}

template <class S>
bool MultiTracker<S>::beyondGate(const std::pair<double, double>& gate, const Pose& guess,
                                 const Pose& pose) {
  const Pose correction = S::normalized(guess.inverse() * pose);
  return S::distance(correction) > gate.first || S::angle(correction) > gate.second;
}

template <class S>
std::optional<std::pair<double, double>> MultiTracker<S>::correctionGate() const {
  // Without the motion model's prediction (constant velocity, no odometry) nothing bounds how
  // far off the guess may be.
  if (max_correction().empty() || !prediction_.model_motion) return std::nullopt;
  double translation = max_correction()[0], rotation = max_correction()[1];
  const std::vector<double>& growth = max_correction_per_motion();
  if (!growth.empty()) {
    const double d = S::distance(*prediction_.model_motion);
    const double a = S::angle(*prediction_.model_motion);
    translation = std::max(translation, growth[0] * d + growth[1] * a);
    rotation = std::max(rotation, growth[2] * d + growth[3] * a);
  }
  if (prediction_.model_extrapolated) {
    // The extrapolated part was not measured: the robot went anywhere between standing still
    // at the reading and keeping its velocity, so the gate widens by all of it.
    translation += S::distance(*prediction_.model_extrapolated);
    rotation += S::angle(*prediction_.model_extrapolated);
  }
  return std::make_pair(translation, rotation);
}

template <class S>
void MultiTracker<S>::count(const Frame& frame, const AlignResult<S>& aligned) {
  if (aligned.valid) {
    ++stats_.aligned;
    stats_.inlier_ratio_sum += aligned.inlierRatio();
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
typename S::Matrix MultiTracker<S>::fallbackInformation() const {
  typename S::Matrix information = S::Matrix::Zero();
  for (int i = 0; i < S::kDof; ++i)
    information(i, i) = 1.0 / (fallback_sigma()[i] * fallback_sigma()[i]);
  return information;
}

template <class S>
void MultiTracker<S>::merge(const Frame& frame) {
  for (auto& slice : slices) slice->merge(frame, map_->scene, pose_);
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
void MultiTracker<S>::writeEstimate(Frame& frame, bool lost) const {
  frame.estimate.valid = true;
  frame.estimate.local_map = map_->id;
  frame.estimate.in_map = S::to3D(pose_);
  frame.estimate.frozen = false;  // the back-end may still move this map
  frame.estimate.lost = lost;
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
  motion_residual_.reset();
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
  if (map_) throw InputError("localization can only start before the first frame");
  return Localizer<S>::create(name(), aligner.shared(), motion.shared(), constant_velocity(),
                              localize_tie(), std::move(maps));
}

template class MultiTracker<Space2D>;
template class MultiTracker<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
