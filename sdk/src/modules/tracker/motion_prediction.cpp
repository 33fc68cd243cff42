// MotionPrediction: the motion model's estimate, else constant velocity with a covariance bounded
// by the plausible accelerations and narrowed by how far constant velocity has been off.
#include <cmath>

#include "plugslam/motion_model.h"

namespace plugslam {
inline namespace abi_v1 {
namespace {

// The name of the one raw entry `model` reads; empty when it reads none or several.
template <class S>
std::string soleRawInput(const MotionModel<S>& model) {
  std::string name;
  int inputs = 0;
  for (const EntryBase* e : model.entries())
    if (!e->writes() && e->container() == Container::raw) {
      ++inputs;
      name = e->name();
    }
  return inputs == 1 ? name : std::string();
}

// Constant velocity's error is learned from this many recent measured frames: enough that one
// odd step does not narrow or widen the next window much, few enough to follow a change of
// pace (a robot that starts turning in place).
constexpr int kErrorWindow = 20;
// Before this many measured frames the spread of the errors is not known: the bounds alone hold.
constexpr int kMinErrors = 5;

}  // namespace

template <class S>
MotionEstimate<S> MotionPrediction<S>::predict(MotionModel<S>* model,
                                               const ConstantVelocityBounds& bounds,
                                               const Frame& frame) {
  model_motion.reset();
  model_entry.clear();
  typical.reset();
  through_gap.reset();
  guessed_.reset();
  interval_ = last_stamp_ ? frame.stamp - *last_stamp_ : 0.0;
  last_stamp_ = frame.stamp;
  if (model) {
    model_motion = model->predict(frame);
    if (model_motion) {
      model_entry = soleRawInput(*model);
      return *model_motion;
    }
  }
  // A sensor runs at a steady rate, and a log's stamps say when a frame arrived, give or take
  // the logger's buffering (some logs' stamps go backwards): a frame within twice the typical
  // interval of the last one came at the usual rate; only a longer gap (a dropped scan, a
  // pause) is time the robot had to change its velocity. The velocity is the mean over the
  // last steps, per step.
  const double n = static_cast<double>(steps_.size());
  double sum = 0;
  for (const auto& step : steps_) sum += std::max(step.first, 0.0);
  const double usual = n > 0 ? sum / n : 0.0;
  const bool gap = usual > 0 && interval_ > 2 * usual;
  const double dt = gap ? interval_ : usual;
  // Known at the middle of the steps averaged; from there to the middle of this one the
  // velocity may change by at most acceleration x (their time + this) / 2, and the position by
  // that times this step's duration. Before a step was seen (the second frame, after a reset)
  // the velocity is unknown: the prediction says nothing (a standard deviation no search
  // window or prior is narrowed by).
  const bool known = n > 0;
  typename S::Vector per_step = S::Vector::Zero();
  if (known) {
    Pose total = Pose::Identity();
    for (const auto& step : steps_) total = total * step.second;
    per_step = S::toVector(S::normalized(total)) / n;
  }
  // The mean is one step at that velocity: over a gap the robot may have gone on, slowed or
  // stopped, which the covariance, not the mean, follows.
  const Pose mean = S::normalized(S::boxplus(Pose::Identity(), per_step));
  const double reach = dt * 0.5 * (n * usual + dt);
  const double usual_reach = usual * 0.5 * (n + 1) * usual;
  const double st =
      known ? std::max(bounds.min_sigma_translation, bounds.acceleration * reach) : kUnknown;
  const double sr =
      known ? std::max(bounds.min_sigma_rotation, bounds.angular_acceleration * reach) : kUnknown;
  MotionEstimate<S> e = MotionEstimate<S>::isotropic(mean, st, sr);
  if (!known) return e;
  guessed_ = mean;
  if (gap)
    through_gap = S::normalized(S::boxplus(Pose::Identity(), per_step * (interval_ / usual)));
  stretch_ = usual_reach > 0 ? reach / usual_reach : 1.0;
  // The bounds hold for any robot; this one's recent steps say how much it really changes its
  // velocity from one frame to the next (a log that keeps a scan per metre driven changes it far
  // less than the seconds between its scans would allow): the typical error, never wider than
  // the bound. A gap stretches it as it does the bound.
  if (errors_ >= kMinErrors) {
    typical = e.covariance;
    for (int i = 0; i < S::kDof; ++i) {
      const double floor = i < S::kDim ? bounds.min_sigma_translation : bounds.min_sigma_rotation;
      const double learned = std::max(floor, std::sqrt(error_ms_(i)) * stretch_);
      (*typical)(i, i) = std::min(e.covariance(i, i), learned * learned);
    }
  }
  return e;
}

template <class S>
AlignContext<S> MotionPrediction<S>::context(const Pose& previous, const Pose& guess,
                                             const MotionEstimate<S>& predicted) const {
  std::optional<Pose> measured;
  if (model_motion) measured = model_motion->mean;
  AlignContext<S> c{previous, guess, measured, model_entry};
  // The covariance is in the robot's own tangent (boxplus multiplies on the right), which a
  // change of scene frame leaves as it is.
  c.covariance = predicted.covariance;
  c.typical = typical;
  if (through_gap) c.through_gap = S::normalized(previous * *through_gap);
  return c;
}

template <class S>
void MotionPrediction<S>::solved(const Pose& motion, bool measured) {
  steps_.emplace_back(interval_, motion);
  while (steps_.size() > kMaxSteps) steps_.pop_front();
  if (guessed_ && measured) {
    const typename S::Vector error =
        S::toVector(S::normalized(guessed_->inverse() * motion)) / std::max(stretch_, 1e-9);
    ++errors_;
    const double weight = 1.0 / std::min(errors_, kErrorWindow);
    error_ms_ += weight * (error.cwiseAbs2() - error_ms_);
  }
  guessed_.reset();
  through_gap.reset();
}

template <class S>
void MotionPrediction<S>::reset() {
  steps_.clear();
  interval_ = 0;
  last_stamp_.reset();
  model_motion.reset();
  model_entry.clear();
  typical.reset();
  through_gap.reset();
  guessed_.reset();
  // How far constant velocity is off is the robot's (and the log's rate's), not the history's:
  // it survives a reset.
}

template struct MotionPrediction<Space2D>;
template struct MotionPrediction<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
