// The dense depth cue's slices on ray-cast depth of a box-shaped room: the factor passes the
// SDK's Jacobian check (free camera, and a camera on a planar robot), the aligner slice alone
// recovers a known motion and vouches for as many directions as its surfaces pin (none at a
// pose off the surface) and relocalises a view 2.4 m from its guess by planes against an anchor;
// the keyframe slice keeps, renews and hands over its keyframe and keeps the keyframes it
// replaced apart from each other as anchors; the keyframe survives a session archive, and one
// written before anchors existed still loads.
#include <gtest/gtest.h>

#include <memory>
#include <sstream>

#include "depth_slices.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/slice_check.h"
#include "room_depth.h"
#include "round_trip.h"

namespace plugslam::rgbd {
namespace {

using namespace plugslam::rgbd::testing;

CameraInfo cameraInfo(const Eigen::Isometry3d& mount = Eigen::Isometry3d::Identity()) {
  CameraInfo c;
  c.setIntrinsics(pinhole());
  c.mount = mount;
  c.second = pinhole();  // depth registered to colour
  return c;
}

Frame depthFrame(uint64_t seq, const DepthImage& depth, const CameraInfo& camera) {
  Frame f;
  f.seq = seq;
  f.raw.set<DepthImage>("depth", depth);
  f.raw.set<CameraInfo>("camera", camera);
  return f;
}

// A scene holding the keyframe the keyframe slice takes from the camera at `camera_pose`.
PropertyContainer keyframeScene(const SE3& camera_pose,
                                const std::vector<Plane>& planes = room()) {
  PropertyContainer scene;
  DepthKeyframeSlice<Space3D> k;
  k.configure();
  k.merge(depthFrame(0, render(planes, camera_pose), cameraInfo()), scene, camera_pose);
  return scene;
}

// The inliers the slice alone counts at `at` for a frame seen from `truth` (it joins at once).
size_t inliersAt(const std::vector<Plane>& planes, const SE3& truth, const SE3& at,
                 size_t* factors = nullptr) {
  const PropertyContainer scene = keyframeScene(SE3::Identity(), planes);
  DepthSlice<Space3D> slice;
  slice.first_round = 0;
  slice.configure();
  AlignContext<Space3D> ctx{SE3::Identity(), at};
  EXPECT_TRUE(slice.bind(depthFrame(1, render(planes, truth), cameraInfo()), scene, ctx));
  slice.associate(at);
  NormalEquations<Space3D> eq;
  slice.linearize(at, eq);
  if (factors) *factors = eq.factors;
  return eq.inliers;
}

TEST(DepthSlice3D, ItsFactorsPassTheSdkJacobianCheck) {
  const PropertyContainer scene = keyframeScene(SE3::Identity());
  const SE3 truth = motion({0.02, -0.05, 0.01}, {0.1, 0.0, 0.2});
  DepthSlice<Space3D> slice;
  slice.first_round = 0;
  slice.configure();
  AlignContext<Space3D> ctx{SE3::Identity(), truth};
  ASSERT_TRUE(slice.bind(depthFrame(1, render(room(), truth), cameraInfo()), scene, ctx));
  const SE3 t = motion({0.003, 0.002, -0.004}, {0.01, -0.005, 0.008}) * truth;
  slice.associate(t);
  const SliceJacobianCheck r = checkSliceJacobians(slice, t);
  EXPECT_GT(r.factors, 1000u);
  EXPECT_TRUE(r.ok()) << r;
}

TEST(DepthSlice2D, ItsFactorsPassTheSdkJacobianCheckThroughAMount) {
  // A camera looking along a planar robot's x axis, 0.3 m ahead and 1 m up (as the mixed world's).
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
  mount.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  mount.translation() << 0.3, 0.0, 1.0;
  const Eigen::Isometry2d robot = se2(0.2, -0.1, 0.05);
  // The keyframe from the robot at the origin; the frame from `robot`, both through the mount.
  PropertyContainer scene;
  DepthKeyframeSlice<Space2D> k;
  k.configure();
  k.merge(depthFrame(0, render(room(), mount), cameraInfo(mount)), scene,
          Eigen::Isometry2d::Identity());
  DepthSlice<Space2D> slice;
  slice.first_round = 0;
  slice.configure();
  AlignContext<Space2D> ctx{Eigen::Isometry2d::Identity(), robot};
  const SE3 camera = Space2D::to3D(robot) * mount;
  ASSERT_TRUE(slice.bind(depthFrame(1, render(room(), camera), cameraInfo(mount)), scene, ctx));
  const Eigen::Isometry2d t = robot * se2(0.01, -0.01, 0.004);
  slice.associate(t);
  const SliceJacobianCheck r = checkSliceJacobians(slice, t);
  EXPECT_GT(r.factors, 1000u);
  EXPECT_TRUE(r.ok()) << r;
}

TEST(DepthSlice3D, AloneRecoversAKnownMotionAndVouchesForAllSixDirections) {
  const PropertyContainer scene = keyframeScene(SE3::Identity());
  const SE3 truth = motion({0.03, -0.06, 0.02}, {0.12, -0.03, 0.15});
  auto slice = std::make_shared<DepthSlice<Space3D>>();
  slice->first_round = 0;  // no other cue to pull the pose first
  slice->configure();
  MultiAligner<Space3D> aligner;
  aligner.slices.assign(slice);
  aligner.min_inliers = 0;
  // 2 cm and 1 deg off, inside the projective association's basin.
  const SE3 start = motion({0.01, 0.01, -0.005}, {0.02, 0.01, -0.01}) * truth;
  AlignContext<Space3D> ctx{SE3::Identity(), start};
  const AlignResult<Space3D> r =
      aligner.align(depthFrame(1, render(room(), truth), cameraInfo()), scene, ctx);
  EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 1e-3);
  EXPECT_LT(degrees(truth.inverse() * r.pose), 0.02);
  EXPECT_GT(r.factors, 4000u);  // of 80 x 60 sampled readings
  // A room's corner pins every direction: one surface, counted once per direction.
  EXPECT_EQ(r.inliers, 6u);
}

TEST(DepthSlice3D, VouchesOnlyForTheDirectionsAWallPins) {
  // A wall 3 m ahead fixes the depth axis and the two tilts; sliding along it or turning about
  // its normal moves no reading off it.
  const std::vector<Plane> wall{{{0, 0, 1}, 3.0}};
  const SE3 truth = motion({0.01, -0.02, 0.0}, {0.05, 0.02, 0.03});
  size_t factors = 0;
  EXPECT_EQ(inliersAt(wall, truth, truth, &factors), 3u);
  EXPECT_GT(factors, 4000u);
  EXPECT_EQ(inliersAt(room(), truth, truth), 6u);
}

TEST(DepthSlice3D, DoesNotVouchForAPoseOffTheSurface) {
  const SE3 truth = motion({0.01, -0.02, 0.0}, {0.05, 0.02, 0.03});
  // The room's readings are 1-5 m away, where a Kinect's pair of readings is uncertain by
  // 1-5 cm: a pose 2 cm off every wall is within their noise, and the cue rightly vouches.
  EXPECT_EQ(inliersAt(room(), truth, truth * motion({0, 0, 0}, {0.012, 0.012, 0.012})), 6u);
  // 10 cm off every wall, or turned by 6 degrees: the readings still pair, but too many lie
  // off their surface.
  size_t factors = 0;
  EXPECT_EQ(inliersAt(room(), truth, truth * motion({0, 0, 0}, {0.06, 0.06, 0.06}), &factors),
            0u);
  EXPECT_GT(factors, 1000u);
  EXPECT_EQ(inliersAt(room(), truth, truth * motion({0, 0.1, 0}, {0, 0, 0})), 0u);
}

TEST(DepthSlice3D, WaitsForTheFirstRoundItJoinsAt) {
  const PropertyContainer scene = keyframeScene(SE3::Identity());
  DepthSlice<Space3D> slice;  // first_round 1: the second association round
  slice.configure();
  AlignContext<Space3D> ctx{SE3::Identity(), SE3::Identity()};
  ASSERT_TRUE(slice.bind(depthFrame(1, render(room(), SE3::Identity()), cameraInfo()), scene, ctx));
  NormalEquations<Space3D> eq;
  slice.associate(SE3::Identity());
  slice.linearize(SE3::Identity(), eq);
  EXPECT_EQ(eq.factors, 0u);
  slice.associate(SE3::Identity());
  slice.linearize(SE3::Identity(), eq);
  EXPECT_GT(eq.factors, 1000u);
  EXPECT_LT(eq.chi2, 1e-6);
}

TEST(DepthSlice3D, RelocalisesAFarViewByItsPlanesAgainstAnAnchor) {
  // The keyframe looks away from the room's corner; the anchor it replaced looked into it. The
  // frame sees the corner from 2.4 m away and 30 deg aside, and its guess is the keyframe's pose.
  PropertyContainer scene;
  DepthKeyframeSlice<Space3D> k;
  k.configure();
  const SE3 away = lookAt({0.0, 0.0, 0.0}, -kCorner);
  k.merge(depthFrame(0, render(room(), cornerView()), cameraInfo()), scene, cornerView());
  k.merge(depthFrame(1, render(room(), away), cameraInfo()), scene, away);
  ASSERT_EQ(scene.get<DepthKeyframe>("depth_keyframe").anchors.size(), 1u);
  const SE3 truth = lookAt({-1.2, -0.3, 2.0}, kCorner);
  const Frame frame = depthFrame(2, render(room(), truth, 0.002, 3), cameraInfo());

  auto slice = std::make_shared<DepthSlice<Space3D>>();
  slice->first_round = 0;
  slice->configure();
  MultiAligner<Space3D> aligner;
  aligner.slices.assign(slice);
  aligner.min_inliers = 6;  // all the directions the corner pins: a valid solve is a right one
  AlignContext<Space3D> ctx{away, away};
  const AlignResult<Space3D> r = aligner.align(frame, scene, ctx);
  ASSERT_TRUE(r.valid) << "failure " << static_cast<int>(r.failure);
  EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 0.005);
  EXPECT_LT(degrees(truth.inverse() * r.pose), 0.1);
  EXPECT_EQ(r.inliers, 6u);
  double relocalised = -1;
  for (const Statistic& st : slice->statistics())
    if (st.name == "relocalised") relocalised = st.value;
  EXPECT_EQ(relocalised, 1.0);

  // With the anchor gone, nothing the keyframe saw places the frame: no guess, and no solve.
  scene.get<DepthKeyframe>("depth_keyframe").anchors.clear();
  ASSERT_TRUE(slice->bind(frame, scene, ctx));
  EXPECT_FALSE(slice->recoverPose().has_value());
  EXPECT_FALSE(aligner.align(frame, scene, ctx).valid);
}

TEST(DepthKeyframeSlice3D, KeepsRenewsAndHandsOverItsKeyframe) {
  DepthKeyframeSlice<Space3D> k;
  k.configure();  // stride 2, renewed after 0.1 m or 0.1 rad
  PropertyContainer scene;
  const SE3 a = SE3::Identity(), b = motion({0, 0.05, 0}, {0.05, 0, 0}),
            c = motion({0, 0.05, 0}, {0.15, 0, 0});
  k.merge(depthFrame(0, render(room(), a), cameraInfo()), scene, a);
  const DepthKeyframe& kf = scene.get<DepthKeyframe>("depth_keyframe");
  EXPECT_EQ(kf.depth.width, kW / 2);
  EXPECT_DOUBLE_EQ(kf.camera.fx, kF / 2);
  EXPECT_EQ(kf.seq, 0u);
  k.merge(depthFrame(1, render(room(), b), cameraInfo()), scene, b);
  EXPECT_EQ(scene.get<DepthKeyframe>("depth_keyframe").seq, 0u);  // 5 cm, 2.9 deg: kept
  k.merge(depthFrame(2, render(room(), c), cameraInfo()), scene, c);
  EXPECT_EQ(scene.get<DepthKeyframe>("depth_keyframe").seq, 2u);  // 15 cm: renewed
  EXPECT_TRUE(scene.get<DepthKeyframe>("depth_keyframe").pose.isApprox(c));
  // A split at `origin`: the keyframe moves into the new map's frame.
  const SE3 origin = motion({0, 0.3, 0}, {1.0, 0, 0.5});
  PropertyContainer next;
  k.handOver(scene, next, origin, 2);
  EXPECT_TRUE(next.get<DepthKeyframe>("depth_keyframe").pose.isApprox(origin.inverse() * c));
}

TEST(DepthKeyframeSlice3D, KeepsTheKeyframesItReplacesApartAsAnchors) {
  DepthKeyframeSlice<Space3D> k;
  k.anchors = 3;
  k.configure();  // anchors 0.5 m or 0.5 rad apart, every 2nd pixel of the keyframe's
  const auto at = [](double x, double turn) { return motion({0, turn, 0}, {x, 0, 0}); };
  // Every pose renews the keyframe (0.1 m or more from the last); the keyframe each replaces is
  // kept when it lies apart from every anchor: seq 0; seq 1 and 2 (0.15 m, 0.3 m: near seq 0)
  // are not; seq 3 (0.6 m) and 4 (1.2 m) are; seq 5 stands where seq 4 does but turned 0.6 rad
  // and is kept too, and past three anchors the one farthest from the camera (seq 0) goes.
  const std::vector<SE3> poses{at(0, 0),   at(0.15, 0), at(0.3, 0),  at(0.6, 0),
                               at(1.2, 0), at(1.2, 0.6), at(1.4, 0.6)};
  PropertyContainer scene;
  for (size_t i = 0; i < poses.size(); ++i)
    k.merge(depthFrame(i, render(room(), poses[i]), cameraInfo()), scene, poses[i]);
  const DepthKeyframe& kf = scene.get<DepthKeyframe>("depth_keyframe");
  EXPECT_EQ(kf.seq, 6u);
  std::vector<uint64_t> seqs;
  for (const DepthView& a : kf.anchors) seqs.push_back(a.seq);
  EXPECT_EQ(seqs, (std::vector<uint64_t>{3, 4, 5}));
  for (const DepthView& a : kf.anchors) {
    EXPECT_TRUE(a.pose.isApprox(poses[a.seq])) << "anchor " << a.seq;
    EXPECT_EQ(a.depth.width, kW / 4);  // every 2nd pixel of the keyframe's every 2nd
    EXPECT_EQ(a.camera.width, kW / 4);
    EXPECT_DOUBLE_EQ(a.camera.fx, kF / 4);
  }
  // A split moves the anchors into the new map's frame with the keyframe.
  const SE3 origin = motion({0, 0.3, 0}, {1.0, 0, 0.5});
  PropertyContainer next;
  k.handOver(scene, next, origin, 6);
  const DepthKeyframe& moved = next.get<DepthKeyframe>("depth_keyframe");
  ASSERT_EQ(moved.anchors.size(), 3u);
  for (const DepthView& a : moved.anchors)
    EXPECT_TRUE(a.pose.isApprox(origin.inverse() * poses[a.seq])) << "anchor " << a.seq;

  // No anchors kept when there are to be none.
  DepthKeyframeSlice<Space3D> none;
  none.anchors = 0;
  none.configure();
  PropertyContainer bare;
  for (size_t i = 0; i < poses.size(); ++i)
    none.merge(depthFrame(i, render(room(), poses[i]), cameraInfo()), bare, poses[i]);
  EXPECT_TRUE(bare.get<DepthKeyframe>("depth_keyframe").anchors.empty());
}

TEST(DepthKeyframe, SurvivesASessionArchive) {
  PropertyContainer scene;
  DepthKeyframeSlice<Space3D> k;
  k.configure();
  const SE3 a = motion({0.1, 0.2, 0.3}, {1, 2, 3}), b = motion({0.1, 0.9, 0.3}, {1, 2, 3});
  k.merge(depthFrame(0, render(room(), a), cameraInfo()), scene, a);
  k.merge(depthFrame(1, render(room(), b), cameraInfo()), scene, b);
  const DepthKeyframe& kf = scene.get<DepthKeyframe>("depth_keyframe");
  ASSERT_EQ(kf.anchors.size(), 1u);
  for (ArchiveFormat format : {ArchiveFormat::kBinary, ArchiveFormat::kText}) {
    const DepthKeyframe back = plugslam::testing::roundTrip(format, kf);
    EXPECT_EQ(back.depth.data, kf.depth.data);
    EXPECT_DOUBLE_EQ(back.camera.cx, kf.camera.cx);
    EXPECT_TRUE(back.pose.isApprox(kf.pose, 1e-12));
    EXPECT_EQ(back.seq, kf.seq);
    ASSERT_EQ(back.anchors.size(), 1u);
    EXPECT_EQ(back.anchors[0].depth.data, kf.anchors[0].depth.data);
    EXPECT_EQ(back.anchors[0].camera.width, kf.anchors[0].camera.width);
    EXPECT_TRUE(back.anchors[0].pose.isApprox(kf.anchors[0].pose, 1e-12));
    EXPECT_EQ(back.anchors[0].seq, 0u);
  }
}

TEST(DepthKeyframe, WrittenBeforeAnchorsExistedLoadsWithNone) {
  // A session of an earlier version holds the view's fields alone: as a DepthView writes them.
  const PropertyContainer scene = keyframeScene(cornerView());
  const DepthKeyframe& kf = scene.get<DepthKeyframe>("depth_keyframe");
  for (ArchiveFormat format : {ArchiveFormat::kBinary, ArchiveFormat::kText}) {
    std::stringstream io;
    {
      auto out = makeOutArchive(io, format);
      save(*out, static_cast<const DepthView&>(kf));
      out->finish();
    }
    DepthKeyframe back;
    back.anchors.resize(2);  // what was there before is replaced
    auto in = makeInArchive(io, format);
    load(*in, back);
    EXPECT_EQ(back.depth.data, kf.depth.data);
    EXPECT_TRUE(back.pose.isApprox(kf.pose, 1e-12));
    EXPECT_TRUE(back.anchors.empty());
  }
}

}  // namespace
}  // namespace plugslam::rgbd
