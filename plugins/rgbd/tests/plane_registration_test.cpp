// Plane-based registration on ray-cast depth images of a box-shaped room: the planes of a view
// are found with their true normals and offsets, two views 36 degrees and more than a metre apart
// are registered with no prediction at all, and the agreement check tells the true pose from a
// wrong one by the free space the fixed camera saw.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "depth_alignment.h"
#include "plane_registration.h"
#include "room_depth.h"

namespace plugslam::rgbd {
namespace {

using namespace plugslam::rgbd::testing;

TEST(PlaneRegistration, FindsTheRoomsPlanesWithTheirOffsets) {
  const SE3 pose = cornerView();  // world <- camera
  const DepthSurface s = makeDepthSurface(render(room(), pose), pinhole());
  const std::vector<DepthPlane> planes = extractPlanes(s, DepthNoiseModel{});
  ASSERT_GE(planes.size(), 3u);
  for (size_t i = 1; i < planes.size(); ++i) EXPECT_GE(planes[i - 1].support, planes[i].support);
  // Each plane found is one of the room's, seen from the camera: n_cam = R^T n_world pointing at
  // the camera, and d the same plane's offset in the camera frame.
  const std::vector<Plane> world = room();
  for (const DepthPlane& p : planes) {
    double best = 1e9, best_d = 1e9;
    for (const Plane& w : world) {
      // The room's normals point outwards, away from any camera inside it; in the camera frame the
      // plane is n_c . x = d_w - n_w . t.
      const Eigen::Vector3d n_c = pose.linear().transpose() * w.n;
      const double d_c = -(w.d - w.n.dot(pose.translation()));
      const double angle = std::acos(std::clamp(n_c.dot(-p.n), -1.0, 1.0));
      if (angle < best) best = angle, best_d = std::abs(p.d - d_c);
    }
    EXPECT_LT(best, 0.01) << "a plane found is no wall of the room";
    EXPECT_LT(best_d, 0.01) << "a plane found is off its wall";
    EXPECT_LT(p.d, 0.0);  // the camera is in front of every plane it sees
  }
}

TEST(PlaneRegistration, RegistersViewsFarApartWithoutAGuess) {
  const SE3 fixed_pose = cornerView();
  // The same corner from 2.4 m away and 30 degrees aside, as a camera that comes back to it from
  // the other side of the room: no keypoint tracker's prediction would reach it.
  const SE3 moving_pose = lookAt({-1.2, -0.3, 2.0}, kCorner);
  const DepthNoiseModel noise;
  const DepthSurface fixed = makeDepthSurface(render(room(), fixed_pose, 0.002, 1), pinhole());
  const DepthSurface moving = makeDepthSurface(render(room(), moving_pose, 0.002, 2), pinhole());
  const std::vector<DepthPlane> fp = extractPlanes(fixed, noise);
  const std::vector<DepthPlane> mp = extractPlanes(moving, noise);
  const std::vector<PlaneHypothesis> h = registerPlanes(fixed, fp, moving, mp, noise);
  ASSERT_FALSE(h.empty());
  const SE3 truth = fixed_pose.inverse() * moving_pose;  // fixed <- moving
  const SE3 error = truth.inverse() * h.front().pose;
  // Three planes, each fitted to thousands of noisy points: a few centimetres and about a degree,
  // near enough for dense alignment to finish.
  EXPECT_LT(error.translation().norm(), 0.03);
  EXPECT_LT(degrees(error), 1.0);
  EXPECT_GT(h.front().agreement.share(), 0.9);
  DepthAlignmentOptions o;
  o.max_distance = 0.1;
  const DepthAlignmentResult r = alignDepth(fixed, moving, h.front().pose, o);
  ASSERT_TRUE(r.ok);
  EXPECT_LT((r.pose.translation() - truth.translation()).norm(), 0.003);
  EXPECT_LT(degrees(truth.inverse() * r.pose), 0.1);
}

TEST(PlaneRegistration, TheFreeSpaceRejectsAWrongPose) {
  const SE3 fixed_pose = cornerView();
  const SE3 moving_pose = fixed_pose * motion({0.0, 0.3, 0.0}, {0.3, 0.0, 0.4});
  const DepthNoiseModel noise;
  const DepthSurface fixed = makeDepthSurface(render(room(), fixed_pose), pinhole());
  const DepthSurface moving = makeDepthSurface(render(room(), moving_pose), pinhole());
  const SE3 truth = fixed_pose.inverse() * moving_pose;
  const SurfaceAgreement right = checkAgreement(fixed, moving, truth, noise);
  // Half a metre forward: the moving points land in front of the walls the fixed camera saw.
  const SE3 wrong = motion({0, 0, 0}, {0.0, 0.0, -0.5}) * truth;
  const SurfaceAgreement off = checkAgreement(fixed, moving, wrong, noise);
  EXPECT_GT(right.checked, 500);
  EXPECT_GT(right.share(), 0.95);
  EXPECT_LT(off.share(), 0.3);
  EXPECT_GT(off.in_front, off.on);
}

TEST(PlaneRegistration, OneWallGivesNoHypothesis) {
  // A single plane fixes three of six directions: registration must not invent the others.
  const std::vector<Plane> wall = {{{0, 0, -1}, -3.0}};
  const DepthNoiseModel noise;
  const DepthSurface a = makeDepthSurface(render(wall, SE3::Identity()), pinhole());
  const DepthSurface b =
      makeDepthSurface(render(wall, motion({0, 0.1, 0}, {0.2, 0, 0})), pinhole());
  const std::vector<DepthPlane> pa = extractPlanes(a, noise);
  const std::vector<DepthPlane> pb = extractPlanes(b, noise);
  ASSERT_EQ(pa.size(), 1u);
  EXPECT_TRUE(registerPlanes(a, pa, b, pb, noise).empty());
}

}  // namespace
}  // namespace plugslam::rgbd
