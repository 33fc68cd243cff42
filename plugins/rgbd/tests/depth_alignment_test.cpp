// Dense depth alignment on ray-cast depth images of a box-shaped room: a known motion is
// recovered from a perturbed start, noise costs what it should, a single wall leaves the
// in-plane motion unconstrained (the conditioning says so), and views that share nothing fail.
#include <gtest/gtest.h>

#include <cmath>

#include "depth_alignment.h"
#include "room_depth.h"

namespace plugslam::rgbd {
namespace {

using namespace plugslam::rgbd::testing;

double deg(const SE3& x) { return degrees(x); }

TEST(DepthAlignment, RecoversAKnownMotionFromAPerturbedStart) {
  const SE3 truth = motion({0.05, -0.12, 0.03}, {0.20, -0.05, 0.30});  // 7.5 deg, 0.36 m
  const DepthSurface fixed = makeDepthSurface(render(room(), SE3::Identity()), pinhole());
  const DepthSurface moving = makeDepthSurface(render(room(), truth), pinhole());
  // 1.5 deg and 3 cm off: about what a dataset's reference is off by (rgbd_depth_check).
  const SE3 start = motion({0.015, 0.02, -0.01}, {0.02, -0.01, 0.02}) * truth;
  DepthAlignmentOptions o;
  o.max_distance = 0.2;
  const DepthAlignmentResult r = alignDepth(fixed, moving, start, o);
  ASSERT_TRUE(r.ok);
  // What is left is the pixel grid: a point paired across a room's edge meets the normal of the
  // other wall (measured 0.11 mm, 0.5 mm RMS), against a start 30 mm and 1.5 deg off.
  EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 5e-4);
  EXPECT_LT(deg(truth.inverse() * r.pose), 0.01);
  EXPECT_GT(r.rms_initial, 0.01);
  EXPECT_LT(r.rms, 1e-3);
  EXPECT_GT(r.pairs, r.points / 2);
  EXPECT_GT(r.conditioning, 1e-4);
}

TEST(DepthAlignment, NoiseCostsLittleOverManyPoints) {
  const SE3 truth = motion({0.0, 0.08, 0.0}, {0.10, 0.0, 0.15});
  // 3 mm of depth noise, about a Kinect's at 2 m.
  const DepthSurface fixed =
      makeDepthSurface(render(room(), SE3::Identity(), 0.003, 1), pinhole());
  const DepthSurface moving = makeDepthSurface(render(room(), truth, 0.003, 2), pinhole());
  const DepthAlignmentResult r = alignDepth(fixed, moving, truth);
  ASSERT_TRUE(r.ok);
  // Thousands of pairs average the noise: well under the 1 cm / 0.5 deg a tracker is held to.
  EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 0.003);
  EXPECT_LT(deg(truth.inverse() * r.pose), 0.1);
  // The residual is the noise of both images along the normal, not zero and not more.
  EXPECT_GT(r.rms, 0.002);
  EXPECT_LT(r.rms, 0.008);
}

TEST(DepthAlignment, ASingleWallLeavesItsInPlaneMotionFree) {
  const std::vector<Plane> wall = {{{0, 0, 1}, 3.0}};
  const DepthSurface fixed = makeDepthSurface(render(wall, SE3::Identity()), pinhole());
  const DepthSurface moving = makeDepthSurface(render(wall, SE3::Identity()), pinhole());
  const DepthAlignmentResult r = alignDepth(fixed, moving, SE3::Identity());
  EXPECT_GT(r.pairs, 1000);
  EXPECT_LT(r.conditioning, 1e-8);  // x, y and the roll about z are not seen by a plane
}

TEST(DepthAlignment, ViewsThatShareNoSurfaceAreNotOk) {
  // The moving camera looks back at the wall behind the fixed one's back.
  const SE3 back = motion({0.0, M_PI, 0.0}, {0.0, 0.0, 0.0});
  const DepthSurface fixed = makeDepthSurface(render(room(), SE3::Identity()), pinhole());
  const DepthSurface moving = makeDepthSurface(render(room(), back), pinhole());
  const DepthAlignmentResult r = alignDepth(fixed, moving, back);
  EXPECT_FALSE(r.ok);
  EXPECT_LT(r.pairs, r.points / 20);
}

TEST(DepthAlignment, NormalsStopAtDepthSteps) {
  DepthImage img;
  img.resize(20, 10);
  for (int v = 0; v < 10; ++v)
    for (int u = 0; u < 20; ++u) img.data[static_cast<size_t>(v * 20 + u)] = u < 10 ? 1.0f : 2.0f;
  const CameraIntrinsics k{20, 20, 9.5, 4.5, 20, 10, {}};
  const DepthSurface s = makeDepthSurface(img, k, 1);
  EXPECT_GT(s.normals[5 * 20 + 5].norm(), 0.99f);   // inside the near plane
  EXPECT_EQ(s.normals[5 * 20 + 9].norm(), 0.0f);    // its neighbour is on the far one
  EXPECT_EQ(s.normals[5 * 20 + 10].norm(), 0.0f);
  EXPECT_GT(s.normals[5 * 20 + 15].norm(), 0.99f);
  EXPECT_NEAR(std::abs(s.normals[5 * 20 + 5].z()), 1.0f, 1e-5f);
}

}  // namespace
}  // namespace plugslam::rgbd
