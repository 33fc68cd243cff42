#pragma once
// MotionModel: predicts the robot's motion between two frames (e.g. from wheel odometry) as a
// mean and a covariance, and the prediction a tracker makes from it. The covariance is the one
// statement of how far the motion may be off: the aligner searches a window it sets and weighs
// its motion prior by it (seed, section III: predict, search, refine).
#include <algorithm>
#include <deque>
#include <optional>
#include <string>
#include <utility>

#include "plugslam/aligner_slice.h"
#include "plugslam/configurable.h"
#include "plugslam/entry.h"
#include "plugslam/frame.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// A relative motion and the covariance of its error, in the tangent space at the mean (right
/// perturbation: the true motion is mean * exp(e), e ~ N(0, covariance)).
template <class S>
struct MotionEstimate {
  typename S::Pose mean = S::Pose::Identity();            ///< the motion
  typename S::Matrix covariance = S::Matrix::Identity();  ///< of its error [m^2, rad^2]
  /// A motion whose error has standard deviation `sigma_t` [m] on every translation axis and
  /// `sigma_r` [rad] on every rotation axis, independently.
  static MotionEstimate isotropic(const typename S::Pose& mean, double sigma_t, double sigma_r) {
    MotionEstimate e;
    e.mean = mean;
    e.covariance.setZero();
    for (int i = 0; i < S::kDim; ++i) e.covariance(i, i) = sigma_t * sigma_t;
    for (int i = S::kDim; i < S::kDof; ++i) e.covariance(i, i) = sigma_r * sigma_r;
    return e;
  }
};

/// Predicts the relative motion since the previous frame it saw, with its uncertainty.
template <class S>
class MotionModel : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "MotionModel2D" : "MotionModel3D";
  using Pose = typename S::Pose;
  ~MotionModel() override;
  /// The motion since the previous call (in the previous robot frame) and its covariance, or
  /// nothing when this frame carries no usable reading.
  virtual std::optional<MotionEstimate<S>> predict(const Frame& frame) = 0;
  /// Forgets the previous reading.
  virtual void reset() {}
};

/// Without a motion model's reading the robot is taken to keep its velocity, and how far that
/// can be wrong follows from how fast it can change it: the largest plausible accelerations.
struct ConstantVelocityBounds {
  double acceleration = 1.0;            ///< [m/s^2] largest plausible linear acceleration
  double angular_acceleration = 2.0;    ///< [rad/s^2] largest plausible angular acceleration
  double min_sigma_translation = 0.01;  ///< [m] floor (a stamp-less or instantaneous step)
  double min_sigma_rotation = 0.005;    ///< [rad] floor
};

/// The parameters that set a tracker's bounds, declared by each tracker as
/// `Param<double> max_acceleration = maxAccelerationParam(this, doc);` so that their names,
/// units, ranges and defaults (ConstantVelocityBounds') are one tracker's as the other's.
Param<double> maxAccelerationParam(Configurable* owner, std::string doc);
/// The angular one (see maxAccelerationParam).
Param<double> maxAngularAccelerationParam(Configurable* owner, std::string doc);
/// The bounds those two parameters set.
ConstantVelocityBounds constantVelocityBounds(double max_acceleration,
                                              double max_angular_acceleration);

/// The motion a tracker predicts before aligning: the motion model's estimate when it has one
/// for the frame, else the recent velocity kept over the time since the last frame, with the
/// covariance the largest plausible accelerations allow over that time and, as `typical`, how
/// far that guess has been off on the recent frames whose step the data measured.
template <class S>
struct MotionPrediction {
  using Pose = typename S::Pose;
  /// The motion model's estimate for the last frame (empty: the prediction is constant
  /// velocity); the aligner's slices get it in their AlignContext.
  std::optional<MotionEstimate<S>> model_motion;
  /// The raw entry `model_motion` was measured from when the model reads exactly one (a slice
  /// reading the same entry then takes that delta rather than computing it again); else empty.
  std::string model_entry;
  /// With a constant-velocity prediction, once enough of its errors were measured: their
  /// covariance (the prediction's covariance bounds them and sets the search window; the search
  /// favours poses within this). Empty otherwise.
  std::optional<typename S::Matrix> typical;
  /// After a gap in the stamps (a frame more than twice the usual interval after the last), the
  /// motion had the robot kept its velocity through the gap. The mean assumes one step (a logger
  /// that writes a frame when the robot has moved); a sensor that lost frames kept its pace. The
  /// covariance is about either; the aligner tries this one when the other cannot be vouched for.
  std::optional<Pose> through_gap;

  /// The motion predicted for `frame` (in the previous robot frame) and its covariance.
  MotionEstimate<S> predict(MotionModel<S>* model, const ConstantVelocityBounds& bounds,
                            const Frame& frame);
  /// The aligner's context for the frame just predicted (`predicted`, what predict() returned):
  /// the previous pose and the guess in the scene's frame, the model's motion and its entry, the
  /// covariance and the typical error.
  AlignContext<S> context(const Pose& previous, const Pose& guess,
                          const MotionEstimate<S>& predicted) const;
  /// Records the motion the frame just predicted really made; `measured`: the data fixed it
  /// (a valid, unambiguous alignment), so it also tells how far the prediction was off.
  void solved(const Pose& motion, bool measured = false);
  /// Forgets the motion history.
  void reset();

 private:
  static constexpr double kUnknown = 1e3;  // [m, rad] a standard deviation that bounds nothing
  // The velocity is the mean of the last few steps: enough to average the stamps' jitter, few
  // enough to follow a turn.
  static constexpr size_t kMaxSteps = 3;
  std::deque<std::pair<double, Pose>> steps_;  // (stamp interval, motion) of the last frames
  double interval_ = 0;                        // of the frame last predicted
  std::optional<double> last_stamp_;
  // How far constant velocity was off: the mean square of each tangent coordinate of the error
  // (per step of the typical interval) over the recent measured frames, and how many there were.
  typename S::Vector error_ms_ = S::Vector::Zero();
  int errors_ = 0;
  std::optional<Pose> guessed_;  // the last constant-velocity mean, until solved() judges it
  double stretch_ = 1;           // its error's growth over a typical step's (a gap's is larger)
};

extern template class MotionModel<Space2D>;
extern template class MotionModel<Space3D>;
extern template struct MotionPrediction<Space2D>;
extern template struct MotionPrediction<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
