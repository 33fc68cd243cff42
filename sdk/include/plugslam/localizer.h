#pragma once
// Localization in frozen maps: a tracker that follows the robot through the local maps of a
// saved session, choosing at each frame the map that explains it best, and never changing them.
#include <memory>
#include <vector>

#include "plugslam/motion_model.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/tracker.h"

namespace plugslam {
inline namespace abi_v1 {

/// Tracks frames in frozen local maps ("sdk.Localizer2D/3D"). A mapping tracker hands one over
/// for `run --localize` (Tracker::localizer), with its own aligner and motion model.
template <class S>
class Localizer : public Tracker {
 public:
  using Pose = typename S::Pose;

  Slot<MultiAligner<S>> aligner{this, "aligner", std::string("sdk.MultiAligner") + S::kSuffix,
                                "solves for the robot pose against a frozen map"};
  Slot<MotionModel<S>> motion{this, "motion", "",
                              "predicts motion between frames (default: constant velocity)"};
  Param<double> max_acceleration = maxAccelerationParam(
      this,
      "largest plausible linear acceleration: the uncertainty of a constant-velocity "
      "prediction");
  Param<double> max_angular_acceleration =
      maxAngularAccelerationParam(this, "largest plausible angular acceleration");
  Param<double> tie{this,
                    "tie",
                    0.02,
                    "",
                    "maps whose alignment's inlier ratio is within this of the best are equally "
                    "good, and the one nearest the motion prediction wins",
                    Range{0, 1}};

  Localizer();
  ~Localizer() override;
  int dimension() const override { return S::kDim; }
  TrackEvents track(Frame& frame) override;
  void continueSession(int64_t next_id) override;
  std::shared_ptr<Tracker> localizer(
      std::vector<std::shared_ptr<const LocalMap>> maps) const override;
  void relocate(const Eigen::Isometry3d& world) override;
  /// The frozen maps to localize in (before the first frame); throws InputError when there
  /// are none or one is of the other dimension.
  void setMaps(std::vector<std::shared_ptr<const LocalMap>> maps);
  /// A localizer named `name` with these parts and settings, in `maps` (see setMaps).
  static std::shared_ptr<Localizer> create(const std::string& name,
                                           std::shared_ptr<MultiAligner<S>> aligner,
                                           std::shared_ptr<MotionModel<S>> motion,
                                           const ConstantVelocityBounds& bounds, double tie,
                                           std::vector<std::shared_ptr<const LocalMap>> maps);

 private:
  struct State;  // the maps, the map the robot is in, the motion history
  std::unique_ptr<State> state_;
};

extern template class Localizer<Space2D>;
extern template class Localizer<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
