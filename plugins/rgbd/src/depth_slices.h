#pragma once
// The dense depth cue: point-to-plane factors between this frame's depth image and a depth
// keyframe of the local map (KinectFusion's projective ICP, frame to keyframe), in the same
// solve as the landmark cue. It constrains the pose where the image has no corners (a painted
// wall, a room's corner) and adds thousands of depth readings where the keypoints have a few
// hundred. Both slices read the raw depth and calibration, registered to the colour camera as
// the preprocessor does, and work on a planar robot (2D pipelines) as on a free camera.
#include <cstdint>
#include <memory>
#include <vector>

#include "depth_alignment.h"
#include "depth_model.h"
#include "depth_registration.h"
#include "plugslam/aligner_slice.h"
#include "plugslam/archive.h"
#include "plugslam/solver/robust_kernel.h"
#include "plugslam/statistics.h"
#include "plugslam/tracker_slice.h"

namespace plugslam {
namespace rgbd {

/// "rgbd.DepthKeyframe": one frame's depth image in the colour camera's pixels, subsampled, with
/// the pinhole of those pixels and the camera's pose in the local map.
struct DepthKeyframe {
  DepthImage depth;                                         ///< [m], 0 = no reading
  CameraIntrinsics camera;                                  ///< pinhole of `depth`'s pixels
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< scene <- camera
  uint64_t seq = 0;                                         ///< the frame it was taken from
  /// True before the first frame is stored.
  bool empty() const { return depth.width == 0; }
};
/// Serializes a depth keyframe (sessions keep the local maps' scenes).
void save(OutArchive& ar, const DepthKeyframe& keyframe);
/// Deserializes a depth keyframe.
void load(InArchive& ar, DepthKeyframe& keyframe);

/// Every `stride`-th pixel of `depth` in both axes, and the pinhole of those pixels.
void subsampleDepth(const DepthImage& depth, const CameraIntrinsics& camera, int stride,
                    DepthImage& out_depth, CameraIntrinsics& out_camera);

/// A point of the moving frame against the keyframe's plane under it, in the scene frame: the
/// dense cue's typed factor, e = n . (T p - q) (the Jacobian restricted to the pose space).
template <class S>
struct DepthPointToPlane {
  using Space = S;                                     ///< the pose space of T
  static constexpr int kErrorDim = 1;                  ///< signed distance to the plane
  using Error = Eigen::Matrix<double, 1, 1>;           ///< e
  using Jacobian = Eigen::Matrix<double, 1, S::kDof>;  ///< de / dx
  Eigen::Vector3d p;                                   ///< moving point, robot frame
  Eigen::Vector3d q;                                   ///< keyframe point, scene frame
  Eigen::Vector3d n;                                   ///< keyframe normal, scene frame
  /// The error at T.
  Error error(const typename S::Pose& t) const;
  /// The error and its Jacobian at T.
  void errorAndJacobian(const typename S::Pose& t, Error& e, Jacobian& j) const;
};

/// The raw entries both depth slices read: the depth image and the calibration it goes with.
struct RawDepthEntries {
  /// Declares the entries on `owner`.
  explicit RawDepthEntries(Configurable* owner)
      : depth{owner, Container::raw, "depth", "depth", "the depth image (metres, 0 = no reading)"},
        camera{owner, Container::raw, "camera", "camera",
               "the calibration (colour camera; second = depth camera)"} {}
  Input<DepthImage> depth;   ///< metres, 0 = no reading
  Input<CameraInfo> camera;  ///< the colour camera; `second` = the depth camera
};

/// "rgbd.DepthSlice2D/3D": projective association of this frame's depth points with the local
/// map's depth keyframe and Huber-robust point-to-plane factors, each weighted by both
/// readings' depth noise and by how many of the sampled readings are independent. Its pairs
/// are not inliers one by one: a smooth surface pairs with itself at a wrong pose too, and its
/// thousands of readings are one surface, not thousands of independent witnesses. It vouches
/// for the pose as a whole instead: when most of the frame's readings lie on the keyframe's
/// surface, it counts one inlier per pose direction its pairs pin (a wall pins three of six, a
/// room's corner all six), so a frame whose other cues have a few inliers short of the aligner's
/// min_inliers still passes where its depth agrees, and a frame the depth does not confirm does
/// not.
template <class S>
class DepthSlice final : public AlignerSlice<S>, public StatisticsSource {
 public:
  using Pose = typename S::Pose;
  RawDepthEntries raw{this};  ///< the keys `depth` and `camera`
  Input<DepthKeyframe> scene{this, Container::scene, "scene", "depth_keyframe",
                             "the local map's depth keyframe to align to"};
  Param<int> stride{this, "stride", 4, "px",
                    "use every stride-th depth pixel in both axes (VGA: 19200 points at 4)",
                    Range{1, 64}};
  Param<double> max_distance{this, "max_distance", 0.05, "m",
                             "a point farther than this plus three sigmas of both readings from "
                             "the keyframe point it projects onto lies on another surface",
                             Range{1e-4, 10}};
  Param<double> correlation{this, "correlation", 9.0, "px",
                            "pixels over which depth errors are shared: a structured-light "
                            "sensor matches 9x9 windows (Kinect v1), so readings closer than "
                            "this are not independent and weigh as one",
                            Range{1, 1000}};
  Param<double> kernel_scale{this, "kernel_scale", 2.0, "sigma",
                             "Huber kernel width in units of each residual's sigma",
                             Range{1e-3, 1e3}};
  Param<int> first_round{this, "first_round", 1, "",
                         "association round the cue joins at (0: the first): projective pairs "
                         "are right only within a few cm of the pose, so the cue waits for the "
                         "keypoints to pull the pose from the prediction",
                         Range{0, 1000}};
  Param<double> keyframe_distance{this, "keyframe_distance", 0.5, "m",
                                  "no factors while the estimated camera is farther than this "
                                  "from the keyframe (a frozen map's keyframe seen from across "
                                  "the room shares little, and its pairs mislead)",
                                  Range{0, 1e6}};
  // A right pose leaves off the keyframe's surface only what the keyframe did not see: with the
  // keyframe renewed every 0.1 m or 0.1 rad (DepthKeyframeSlice), the view has moved on by at
  // most a sixth of a 60 degree field, and occlusions add little. A wrong pose that still puts
  // that much on the surface slides along it, and the directions it slides in are not pinned,
  // so not counted.
  Param<double> vouch_share{this, "vouch_share", 0.8, "",
                            "the cue counts one inlier per pose direction its pairs pin when at "
                            "least this share of the frame's readings lie within kernel_scale "
                            "sigmas of the keyframe's surface (above 1: never)",
                            Range{0, 2}};
  DepthNoiseParams depth_sigma{this};  ///< depth_sigma_a, _b, _z0: as the preprocessor's

  DepthSlice();
  ~DepthSlice() override;
  void configure() override;
  void associate(const Pose& t) override;
  void linearize(const Pose& t, NormalEquations<S>& eq) const override;
  /// frames, alignment_s, points_per_frame, pairs_per_frame (at the solution).
  std::vector<Statistic> statistics() const override;

 protected:
  bool prepare(const AlignContext<S>& context) override;

 private:
  struct Pair {
    int point;          // index into points_
    Eigen::Vector3d q;  // keyframe point, scene frame
    Eigen::Vector3d n;  // its normal, scene frame
    double sigma;       // of the residual [m]
  };
  DepthRegistration registration_;
  DepthSurface keyframe_;
  uint64_t keyframe_seq_ = ~uint64_t{0};
  Eigen::Isometry3d keyframe_pose_ = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> points_;  // robot frame
  std::vector<double> sigmas_;           // their depth noise
  DepthNoiseModel noise_;                // this frame's (the parameters may change)
  std::vector<Pair> pairs_;
  // How many pose directions the pairs on the keyframe's surface pin at t (0 unless they are
  // vouch_share of the frame's readings); `residuals` are the pairs' at t.
  int pinnedDirections(const Pose& t, const std::vector<double>& residuals) const;
  int vouched_ = 0;  // at the last association
  std::unique_ptr<RobustKernel> kernel_;
  double information_scale_ = 1;
  int round_ = 0;
  uint64_t frames_ = 0, points_total_ = 0, pairs_total_ = 0;
  mutable double time_s_ = 0;
};

/// "rgbd.DepthKeyframeSlice2D/3D": keeps the local map's depth keyframe, taking the frame's
/// depth when the map has none or the camera has moved or turned past the thresholds since the
/// keyframe was taken; on a split the keyframe moves into the new map.
template <class S>
class DepthKeyframeSlice final : public TrackerSlice<S>, public HandoverSlice<S> {
 public:
  using Pose = typename S::Pose;
  RawDepthEntries raw{this};  ///< the keys `depth` and `camera`
  Output<DepthKeyframe> scene{this, Container::scene, "scene", "depth_keyframe",
                              "the local map's depth keyframe"};
  Param<int> stride{this, "stride", 2, "px",
                    "keep every stride-th depth pixel in both axes (the moving points land "
                    "between them; a session stores one keyframe per local map)",
                    Range{1, 64}};
  Param<double> distance{this, "distance", 0.1, "m",
                         "a new keyframe once the camera moved this far from the last: about "
                         "the parallax (a few percent of 1-4 m indoor ranges) past which the "
                         "keyframe misses surfaces the frame sees",
                         Range{0, 1e6}};
  Param<double> angle{this, "angle", 0.1, "rad",
                      "or turned this much (6 deg: a tenth of a depth camera's field of view "
                      "leaves the keyframe)",
                      Range{0, 10}};

  void handOver(const PropertyContainer& previous, PropertyContainer& next, const Pose& origin,
                uint64_t seq) override;

 protected:
  void integrate(const MergeContext<S>& context) override;

 private:
  DepthRegistration registration_;
};

extern template struct DepthPointToPlane<Space2D>;
extern template struct DepthPointToPlane<Space3D>;
extern template class DepthSlice<Space2D>;
extern template class DepthSlice<Space3D>;
extern template class DepthKeyframeSlice<Space2D>;
extern template class DepthKeyframeSlice<Space3D>;

}  // namespace rgbd
}  // namespace plugslam
