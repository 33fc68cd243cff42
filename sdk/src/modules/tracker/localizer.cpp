#include "plugslam/localizer.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

template <class S>
struct Localizer<S>::State {
  std::vector<std::shared_ptr<const LocalMap>> maps;  // frozen
  std::shared_ptr<const LocalMap> located;            // the map the robot is in
  Pose pose = Pose::Identity();                       // robot in `located`
  MotionPrediction<S> prediction;
};

template <class S>
Localizer<S>::Localizer() : state_(std::make_unique<State>()) {}
template <class S>
Localizer<S>::~Localizer() = default;

template <class S>
void Localizer<S>::setMaps(std::vector<std::shared_ptr<const LocalMap>> maps) {
  if (stats_.frames > 0) throw InputError("localization can only start before the first frame");
  if (maps.empty()) throw InputError("localization needs at least one saved local map");
  for (const auto& m : maps)
    if (!m || m->dimension != S::kDim)
      throw InputError("localization: a saved map is not " + std::to_string(S::kDim) + "D");
  state_->maps = std::move(maps);
  state_->located.reset();
}

template <class S>
void Localizer<S>::continueSession(int64_t) {
  throw InputError("tracker '" + name() + "' (" + typeName() +
                   ") localizes in frozen maps; extending a session needs a mapping tracker");
}

template <class S>
std::shared_ptr<Localizer<S>> Localizer<S>::create(
    const std::string& name, std::shared_ptr<MultiAligner<S>> aligner,
    std::shared_ptr<MotionModel<S>> motion, const ConstantVelocityBounds& bounds, double tie,
    std::vector<std::shared_ptr<const LocalMap>> maps) {
  auto out = std::make_shared<Localizer<S>>();
  out->setName(name);
  out->setTypeName(std::string("sdk.Localizer") + S::kSuffix);
  out->aligner.assign(std::move(aligner));
  out->motion.assign(std::move(motion));
  out->max_acceleration = bounds.acceleration;
  out->max_angular_acceleration = bounds.angular_acceleration;
  out->tie = tie;
  out->setMaps(std::move(maps));
  return out;
}

template <class S>
std::shared_ptr<Tracker> Localizer<S>::localizer(
    std::vector<std::shared_ptr<const LocalMap>> maps) const {
  return create(name(), aligner.shared(), motion.shared(),
                constantVelocityBounds(max_acceleration(), max_angular_acceleration()), tie(),
                std::move(maps));
}

template <class S>
void Localizer<S>::relocate(const Eigen::Isometry3d& world) {
  State& st = *state_;
  if (st.maps.empty()) throw InputError("localization: no saved maps to relocate in");
  // In the saved map whose origin is nearest; the next frame's candidates are chosen from there.
  st.located = *std::min_element(st.maps.begin(), st.maps.end(), [&](const auto& a, const auto& b) {
    return (a->origin.translation() - world.translation()).squaredNorm() <
           (b->origin.translation() - world.translation()).squaredNorm();
  });
  st.pose = S::normalized(S::from3D(st.located->origin.inverse() * world));
  st.prediction.reset();
}

template <class S>
TrackEvents Localizer<S>::track(Frame& frame) {
  // The frame is aligned against the map it is in and the maps whose origins are nearest its
  // predicted world pose; the valid alignment explaining most of the frame wins (maps of
  // different passes need not agree where the mapping run closed no loop). Alignments within
  // `tie` of the best inlier ratio are equally good (most are at 1.0), and the one closest to
  // the prediction wins among them: a map that also admits a turned solution (built while the
  // robot turned, a corridor) must not win for being tried first. The pose is kept in the
  // winning map's frame. Nothing is merged or split.
  constexpr size_t kNearest = 3;
  State& st = *state_;
  if (st.maps.empty())
    throw InputError("tracker '" + name() + "' (" + typeName() +
                     ") has no saved maps to localize in (run --session DIR --localize)");
  if (!aligner) throw InputError("tracker '" + name() + "' (" + typeName() + ") has no aligner");
  ++stats_.frames;
  const Eigen::Isometry3d at = st.located ? st.located->origin : Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d previous_world = at * S::to3D(st.pose);
  const MotionEstimate<S> predicted = st.prediction.predict(
      motion.get(), constantVelocityBounds(max_acceleration(), max_angular_acceleration()), frame);
  const Eigen::Isometry3d guess_world = at * S::to3D(S::normalized(st.pose * predicted.mean));
  std::vector<std::pair<double, std::shared_ptr<const LocalMap>>> near;
  for (const auto& m : st.maps)
    if (m != st.located)
      near.emplace_back((m->origin.translation() - guess_world.translation()).norm(), m);
  const size_t k = std::min(kNearest, near.size());
  std::partial_sort(near.begin(), near.begin() + k, near.end(),
                    [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::shared_ptr<const LocalMap>> candidates;
  if (st.located) candidates.push_back(st.located);
  for (size_t i = 0; i < k; ++i) candidates.push_back(near[i].second);
  Pose fallback_guess = Pose::Identity();
  std::shared_ptr<const LocalMap> fallback = k > 0 ? near[0].second : st.located;
  struct Tried {
    std::shared_ptr<const LocalMap> map;
    AlignResult<S> result;
    Pose previous;
    double correction;  // translation [m] + rotation [rad] from the prediction
  };
  std::vector<Tried> valid;
  AlignFailure fallback_failure = AlignFailure::no_data;  // no map near enough to try
  double best_ratio = 0;
  for (const auto& m : candidates) {
    const Eigen::Isometry3d to_map = m->origin.inverse();
    const Pose previous = S::normalized(S::from3D(to_map * previous_world));
    const Pose guess = S::normalized(S::from3D(to_map * guess_world));
    if (m == fallback) fallback_guess = guess;
    AlignResult<S> r =
        aligner->align(frame, m->scene, st.prediction.context(previous, guess, predicted));
    if (!r.valid) {
      if (m == fallback) fallback_failure = r.failure;
      continue;
    }
    const Pose correction = S::normalized(guess.inverse() * r.pose);
    best_ratio = std::max(best_ratio, r.inlierRatio());
    valid.push_back({m, r, previous, S::distance(correction) + S::angle(correction)});
  }
  const Tried* chosen = nullptr;
  for (const auto& t : valid)
    if (t.result.inlierRatio() >= best_ratio - tie() &&
        (!chosen || t.correction < chosen->correction))
      chosen = &t;
  if (chosen) {
    st.located = chosen->map;
    st.pose = chosen->result.pose;
    ++stats_.aligned;
    stats_.inlier_ratio_sum += chosen->result.inlierRatio();
    st.prediction.solved(S::normalized(chosen->previous.inverse() * st.pose),
                         chosen->result.fixesStep());
  } else {
    const Eigen::Isometry3d to_map = fallback->origin.inverse();
    const Pose previous = S::normalized(S::from3D(to_map * previous_world));
    st.located = fallback;
    st.pose = fallback_guess;
    st.prediction.solved(S::normalized(previous.inverse() * st.pose));
    // No saved map explains the frame: the reason is the nearest map's.
    stats_.countFailure(fallback_failure);
    spdlog::debug("frame {}: localization failed in maps near {} ({})", frame.seq, fallback->id,
                  toString(fallback_failure));
  }
  frame.estimate.valid = true;
  frame.estimate.local_map = st.located->id;
  frame.estimate.in_map = S::to3D(st.pose);
  frame.estimate.frozen = true;
  frame.estimate.lost = chosen == nullptr;
  return {};
}

template class Localizer<Space2D>;
template class Localizer<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
