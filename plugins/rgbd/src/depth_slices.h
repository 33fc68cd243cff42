#pragma once
// The dense depth cue: point-to-plane factors between this frame's depth image and a depth
// keyframe of the local map (KinectFusion's projective ICP, frame to keyframe), in the same
// solve as the landmark cue. It constrains the pose where the image has no corners (a painted
// wall, a room's corner) and adds thousands of depth readings where the keypoints have a few
// hundred. Both slices read the raw depth and calibration, registered to the colour camera as
// the preprocessor does, and work on a planar robot (2D pipelines) as on a free camera.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "depth_alignment.h"
#include "depth_model.h"
#include "depth_registration.h"
#include "plane_registration.h"
#include "plugslam/aligner_slice.h"
#include "plugslam/archive.h"
#include "plugslam/solver/robust_kernel.h"
#include "plugslam/statistics.h"
#include "plugslam/tracker_slice.h"

namespace plugslam {
namespace rgbd {

/// One depth view: a frame's depth image in the colour camera's pixels, subsampled, with the
/// pinhole of those pixels and the camera's pose in the local map.
struct DepthView {
  DepthImage depth;                                         ///< [m], 0 = no reading
  CameraIntrinsics camera;                                  ///< pinhole of `depth`'s pixels
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< scene <- camera
  uint64_t seq = 0;                                         ///< the frame it was taken from
  /// True before a view is stored.
  bool empty() const { return depth.width == 0; }
};

/// "rgbd.DepthKeyframe": the view the dense cue aligns to, and the anchors: earlier keyframes it
/// replaced, kept where they lie apart, which a frame the keyframe cannot place (one that came
/// back to a place the camera had left) is relocalised against by their planes.
struct DepthKeyframe : DepthView {
  std::vector<DepthView> anchors;  ///< apart from each other and from the keyframe
};
/// Serializes a depth view.
void save(OutArchive& ar, const DepthView& view);
/// Deserializes a depth view.
void load(InArchive& ar, DepthView& view);
/// Serializes a depth keyframe (sessions keep the local maps' scenes).
void save(OutArchive& ar, const DepthKeyframe& keyframe);
/// Deserializes a depth keyframe (a session written before anchors existed has none).
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
/// not. Where the keyframe cannot place the frame, it relocalises by planes against the keyframe
/// and its anchors (recoverPose), with no prediction: a bare wall or room corner has too few
/// keypoints for the landmark cue's recovery, but its planes fix the pose.
template <class S>
class DepthSlice final : public AlignerSlice<S>,
                         public RecoverableSlice<S>,
                         public StatisticsSource {
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
                                  "the room shares little, and its pairs mislead); a view the "
                                  "frame was relocalised against by its planes is exempt",
                                  Range{0, 1e6}};
  // A right pose leaves off the keyframe's surface only what the keyframe did not see: with the
  // keyframe renewed every 0.1 m or 0.1 rad (DepthKeyframeSlice), the view has moved on by at
  // most a sixth of a 60 degree field, and occlusions add little. A wrong pose that still puts
  // that much on the surface slides along it, and the directions it slides in are not pinned,
  // so not counted.
  Param<double> vouch_share{this, "vouch_share", 0.8, "",
                            "the cue counts one inlier per pose direction its pairs pin when at "
                            "least this share of the frame's readings lie within kernel_scale "
                            "sigmas of the keyframe's surface (above 1: never); against a view "
                            "the frame was relocalised against, of the readings that view saw "
                            "(it is far away and saw only part of the frame's), and a plane "
                            "hypothesis is proposed only when this share of the readings its "
                            "view can judge agree with it",
                            Range{0, 2}};
  // Planes hold thousands of readings each: a quarter of the keyframe's pixels (every 4th of a
  // VGA image's in both axes) fits them as well as all of them, and keeps relocalisation to a
  // few milliseconds.
  Param<int> relocalise_stride{this, "relocalise_stride", 4, "px",
                               "relocalisation by planes reads every stride-th pixel of the "
                               "frame's depth in both axes",
                               Range{1, 64}};
  DepthNoiseParams depth_sigma{this};  ///< depth_sigma_a, _b, _z0: as the preprocessor's

  DepthSlice();
  ~DepthSlice() override;
  void configure() override;
  void associate(const Pose& t) override;
  void linearize(const Pose& t, NormalEquations<S>& eq) const override;
  /// The pose that maps three of this frame's planes onto three of the keyframe's or an
  /// anchor's with the most of the frame's readings on that view's surface (registerPlanes),
  /// when vouch_share of the readings the view can judge agree; the solves that follow align to
  /// that view. Empty when no view shares three planes with the frame.
  std::optional<Pose> recoverPose() override;
  /// frames, alignment_s, points_per_frame, pairs_per_frame (at the solution), relocalised.
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
  // A view with its planes, extracted when relocalisation first needs them.
  struct PlanarView {
    DepthSurface surface;
    std::vector<DepthPlane> planes;
    bool planes_found = false;
  };
  const std::vector<DepthPlane>& planesOf(PlanarView& view) const;
  DepthRegistration registration_;
  PlanarView keyframe_;
  uint64_t keyframe_seq_ = ~uint64_t{0};
  Eigen::Isometry3d keyframe_pose_ = Eigen::Isometry3d::Identity();
  std::map<uint64_t, PlanarView> anchors_;  // the bound keyframe's anchors, by seq
  // What the frame is aligned to: the keyframe, or the view recoverPose placed it against.
  const DepthSurface* target_ = nullptr;
  Eigen::Isometry3d target_pose_ = Eigen::Isometry3d::Identity();
  bool relocalised_ = false;
  const DepthImage* depth_ = nullptr;    // this frame's, in the colour camera's pixels
  std::vector<Eigen::Vector3d> points_;  // robot frame
  std::vector<double> sigmas_;           // their depth noise
  DepthNoiseModel noise_;                // this frame's (the parameters may change)
  std::vector<Pair> pairs_;
  // How many pose directions the pairs on the target's surface pin at t (0 unless they are
  // vouch_share of `readings`); `residuals` are the pairs' at t.
  int pinnedDirections(const Pose& t, const std::vector<double>& residuals,
                       size_t readings) const;
  int vouched_ = 0;  // at the last association
  std::unique_ptr<RobustKernel> kernel_;
  double information_scale_ = 1;
  int round_ = 0;
  uint64_t frames_ = 0, points_total_ = 0, pairs_total_ = 0, relocalised_total_ = 0;
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
  // A replaced keyframe is what a camera that comes back sees again. Views nearer each other
  // than the dense cue's keyframe_distance or half a depth camera's field of view (~60 deg)
  // show the same surfaces, so one of them is enough.
  Param<int> anchors{this, "anchors", 8, "",
                     "replaced keyframes kept as anchors to relocalise against (0: none); past "
                     "this many, the one farthest from the camera goes (8 views 0.5 m apart "
                     "span 4 m of path or more: the room a camera that lost track is most "
                     "likely still in)",
                     Range{0, 1000}};
  Param<double> anchor_distance{this, "anchor_distance", 0.5, "m",
                                "a replaced keyframe becomes an anchor when it is this far from "
                                "every anchor kept",
                                Range{0, 1e6}};
  Param<double> anchor_angle{this, "anchor_angle", 0.5, "rad",
                             "or turned this much from each",
                             Range{0, 10}};
  // Plane fitting needs a few thousand readings per view, not every keyframe pixel; a quarter of
  // them keeps a session's anchors small (77 kB each at VGA).
  Param<int> anchor_stride{this, "anchor_stride", 2, "px",
                           "an anchor keeps every stride-th pixel of its keyframe in both axes",
                           Range{1, 64}};

  void handOver(const PropertyContainer& previous, PropertyContainer& next, const Pose& origin,
                uint64_t seq) override;

 protected:
  void integrate(const MergeContext<S>& context) override;

 private:
  // Keeps `k`, about to be replaced, as an anchor when it lies apart from every anchor kept.
  void keepAsAnchor(DepthKeyframe& k, const Eigen::Isometry3d& camera) const;
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
