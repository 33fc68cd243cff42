// The renderer against analytic geometry (noise off), the built-in worlds, and timing.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>

#include "sim3d/noise.h"
#include "sim3d/renderer.h"
#include "sim3d/simulator.h"
#include "sim3d/trajectory.h"
#include "sim3d/world.h"

namespace plugslam::sim::sim3d {
namespace {

PinholeCamera centredVga() { return {500.0, 480.0, 320.0, 240.0, 640, 480}; }

TEST(Sim3DRender, PlaneFacingTheCameraHasItsExactDistance) {
  World w;
  w.addQuad({2.0, -50.0, -50.0}, {0, 1, 0}, {0, 0, 1}, 100.0, 100.0, Material{}, "wall");
  const PinholeCamera cam = centredVga();
  RenderBuffers buf;
  render(w, cam, lookAlong({0, 0, 0}, {1, 0, 0}), &buf, nullptr);
  DepthImage depth;
  DepthNoise off;
  off.enabled = false;
  makeDepthImage(buf, off, 0, 0, &depth);
  ASSERT_EQ(depth.width, 640);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) ASSERT_EQ(depth.at(x, y), 2.0f) << x << "," << y;
  // The optical-axis pixel sees the plane head on.
  EXPECT_NEAR(buf.incidence[240 * 640 + 320], 1.0, 1e-15);
}

TEST(Sim3DRender, TiltedPlaneDepthsBackProjectOntoThePlane) {
  World w;
  const Eigen::Vector3d u = Eigen::Vector3d(0.3, 1.0, 0.0).normalized();
  w.addQuad({3.0, -20.0, -20.0}, u, {0.1, 0.0, 1.0}, 60.0, 60.0, Material{}, "tilted");
  const Face& f = w.faces()[0];
  const PinholeCamera cam = centredVga();
  const Eigen::Isometry3d T = lookAlong({0.2, -0.1, 0.3}, {1.0, 0.2, -0.1});
  RenderBuffers buf;
  render(w, cam, T, &buf, nullptr);
  int hits = 0;
  for (int y = 0; y < cam.height; y += 7)
    for (int x = 0; x < cam.width; x += 5) {
      const double z = buf.depth[y * cam.width + x];
      if (z == 0.0) continue;
      ++hits;
      const Eigen::Vector3d p =
          T * Eigen::Vector3d((x - cam.cx) / cam.fx * z, (y - cam.cy) / cam.fy * z, z);
      EXPECT_NEAR(f.normal.dot(p - f.origin), 0.0, 1e-11) << x << "," << y;
    }
  EXPECT_GT(hits, 5000);
}

// Independent reference: the slab method in the box's own frame.
bool slab(const Eigen::Isometry3d& box, const Eigen::Vector3d& half, const Eigen::Vector3d& o_w,
          const Eigen::Vector3d& d_w, double* t_near, double* t_far) {
  const Eigen::Vector3d o = box.inverse() * o_w, d = box.linear().transpose() * d_w;
  double t0 = -1e300, t1 = 1e300;
  for (int k = 0; k < 3; ++k) {
    double a = (-half[k] - o[k]) / d[k], b = (half[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  *t_near = t0;
  *t_far = t1;
  return t0 <= t1 && t0 > 0;
}

TEST(Sim3DRender, BoxCornerMatchesTheSlabMethodAtEveryPixel) {
  World w;
  Eigen::Isometry3d box = Eigen::Isometry3d::Identity();
  box.linear() = (Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()))
                     .toRotationMatrix();
  box.translation() = Eigen::Vector3d(3.0, 0.0, 0.0);
  const Eigen::Vector3d size(1.0, 1.2, 0.8);
  w.addBox(box, size, Material{}, "box");
  const PinholeCamera cam = centredVga();
  const Eigen::Isometry3d T = lookAlong({0, 0, 0}, {1, 0, 0});
  RenderBuffers buf;
  render(w, cam, T, &buf, nullptr);
  int hits = 0, checked = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const Eigen::Vector3d r((x - cam.cx) / cam.fx, (y - cam.cy) / cam.fy, 1.0);
      double t0, t1;
      const bool hit = slab(box, 0.5 * size, T.translation(), T.linear() * r, &t0, &t1);
      if (std::abs(t1 - t0) < 1e-6) continue;  // grazing an edge: either answer is right
      ++checked;
      const double z = buf.depth[y * cam.width + x];
      if (!hit) {
        ASSERT_EQ(z, 0.0) << x << "," << y;
        continue;
      }
      ++hits;
      ASSERT_NEAR(z, t0, 1e-12 * t0) << x << "," << y;  // r has z = 1: ray parameter = depth
    }
  EXPECT_GT(hits, 10000);
  EXPECT_GT(checked, 300000);
}

TEST(Sim3DRender, AxisPixelHitsTheNearestBoxEdgeAtItsKnownDistance) {
  World w;
  w.addBox(
      Eigen::Translation3d(3.0, 0.0, 0.0) * Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()),
      {1.0, 1.0, 1.0}, Material{}, "cube");
  const PinholeCamera cam = centredVga();
  RenderBuffers buf;
  render(w, cam, lookAlong({0, 0, 0}, {1, 0, 0}), &buf, nullptr);
  // The vertical edge nearest the camera is at x = 3 - sqrt(1/2) on the optical axis.
  EXPECT_NEAR(buf.depth[240 * 640 + 320], 3.0 - std::sqrt(0.5), 1e-12);
  // One pixel left and right see the two faces meeting there, both slightly farther.
  EXPECT_GT(buf.depth[240 * 640 + 319], buf.depth[240 * 640 + 320]);
  EXPECT_GT(buf.depth[240 * 640 + 321], buf.depth[240 * 640 + 320]);
  EXPECT_NE(buf.face[240 * 640 + 319], buf.face[240 * 640 + 321]);
}

TEST(Sim3DRender, RenderAgreesWithCastRay) {
  const World w = World::livingRoom(3);
  const PinholeCamera cam = PinholeCamera::vga();
  const Eigen::Isometry3d T = livingRoomStart();
  RenderBuffers buf;
  render(w, cam, T, &buf, nullptr);
  for (int y = 3; y < cam.height; y += 41)
    for (int x = 2; x < cam.width; x += 37) {
      const Eigen::Vector3d r((x - cam.cx) / cam.fx, (y - cam.cy) / cam.fy, 1.0);
      RayHit hit;
      ASSERT_TRUE(w.castRay(T.translation(), (T.linear() * r).normalized(), 100.0, &hit));
      EXPECT_NEAR(hit.distance, buf.depth[y * cam.width + x] * r.norm(), 1e-9) << x << "," << y;
    }
}

TEST(Sim3DRender, LivingRoomIsClosedAndTextured) {
  const World w = World::livingRoom(0);
  EXPECT_GT(w.objects().size(), 30u);
  const Trajectory loop = livingRoomLoop(10.0, 3.0);
  Image image;
  image.channels = 1;
  RenderBuffers buf;
  for (const auto& p : loop) {
    render(w, PinholeCamera::vga(), p.pose, &buf, &image);
    for (double z : buf.depth) ASSERT_GT(z, 0.0);  // walls, floor and ceiling everywhere
    double mean = 0, sq = 0;
    for (uint8_t v : image.data) mean += v;
    mean /= image.data.size();
    for (uint8_t v : image.data) sq += (v - mean) * (v - mean);
    EXPECT_GT(std::sqrt(sq / image.data.size()), 20.0);  // not flat
  }
}

TEST(Sim3DWorld, SliceOfABoxIsItsFootprint) {
  World w;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(1.0, 2.0, 0.5);
  w.addBox(pose, {2.0, 1.0, 1.0}, Material{}, "box");
  const auto segments = w.slice(0.3);
  ASSERT_EQ(segments.size(), 4u);  // four sides; top and bottom are parallel to the cut
  double length = 0.0;
  for (const auto& [a, b] : segments) {
    length += (b - a).norm();
    for (const Eigen::Vector2d& p : {a, b}) {
      // Every end point is a footprint corner: local coordinates (+-1, +-0.5).
      const Eigen::Vector2d local = Eigen::Rotation2Dd(-0.5) * (p - Eigen::Vector2d(1.0, 2.0));
      EXPECT_NEAR(std::abs(local.x()), 1.0, 1e-12);
      EXPECT_NEAR(std::abs(local.y()), 0.5, 1e-12);
    }
  }
  EXPECT_NEAR(length, 6.0, 1e-12);
  EXPECT_TRUE(w.slice(1.5).empty());
}

TEST(Sim3DRender, StreetKeepsBuildingsOffTheRoad) {
  const RoadPath road = blockLoop(160.0, 100.0, 12.0, 2.0);
  const World w = World::street(road, {}, 5);
  int buildings = 0;
  for (const Object& o : w.objects()) buildings += o.name == "building";
  EXPECT_GT(buildings, 25);
  // Sideways rays at camera height from the road centre reach no building before the kerb.
  const Trajectory drive = driveAlong(road, 1.65, 8.0, 1.0);
  for (const auto& p : drive) {
    for (double side : {-1.0, 1.0}) {
      RayHit hit;
      const Eigen::Vector3d d = side * p.pose.linear().col(0);
      if (w.castRay(p.pose.translation(), d, 100.0, &hit)) {
        EXPECT_GT(hit.distance, StreetOptions{}.road_half_width);
      }
    }
  }
}

// The cost breakdown printed below (the sim plugin's README quotes it) times the stages one at a
// time; it is only a breakdown of a frame if those stages, run with the scenario's noise, seed
// and exposure, give exactly the frame Simulator3D::render gives. That is asserted, for RGB-D
// (render + shading, image noise, depth noise) and for a stereo pair (two renders + noise). The
// times are printed, not asserted: the machine is shared, and speed is a benchmark's business.
TEST(Sim3DRender, FrameIsItsTimedStagesAndTheirCostIsPrinted) {
  ScenarioOptions o;
  o.duration = 4.0;
  const Simulator3D rgbd = Simulator3D::fromOptions(o);
  Sim3DFrame f;
  rgbd.render(0, &f);  // warm up (noise tables)
  const int n = 20;
  auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) rgbd.render((k * 6) % rgbd.frameCount(), &f);
  const double rgbd_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
  ScenarioOptions so = o;
  so.world = "street";
  so.rig = Rig::kStereo;
  const Simulator3D stereo = Simulator3D::fromOptions(so);
  stereo.render(0, &f);
  t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < n; ++k) stereo.render((k * 7) % stereo.frameCount(), &f);
  const double stereo_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
  // Breakdown of the RGB-D frame: visibility only, plus shading, then the noise stages.
  RenderBuffers buf;
  Image image;
  image.channels = 3;
  DepthImage depth;
  double vis = 0, shade = 0, inoise = 0, dnoise = 0;
  for (int k = 0; k < n; ++k) {
    const size_t index = (k * 6) % rgbd.frameCount();
    const StampedPose& p = rgbd.trajectory()[index];
    const double gain = exposureGain(o.image_noise, o.seed, p.t);
    auto a = std::chrono::steady_clock::now();
    render(rgbd.world(), rgbd.camera(), p.pose, &buf, nullptr);
    auto b = std::chrono::steady_clock::now();
    render(rgbd.world(), rgbd.camera(), p.pose, &buf, &image);
    auto c = std::chrono::steady_clock::now();
    applyImageNoise(o.image_noise, o.seed, index, 0, gain, &image);
    auto d = std::chrono::steady_clock::now();
    makeDepthImage(buf, o.depth_noise, o.seed, index, &depth);
    auto e = std::chrono::steady_clock::now();
    vis += std::chrono::duration<double, std::milli>(b - a).count() / n;
    shade += std::chrono::duration<double, std::milli>((c - b) - (b - a)).count() / n;
    inoise += std::chrono::duration<double, std::milli>(d - c).count() / n;
    dnoise += std::chrono::duration<double, std::milli>(e - d).count() / n;
    rgbd.render(index, &f);
    ASSERT_EQ(f.left.data, image.data) << "RGB image of frame " << index;
    ASSERT_EQ(f.depth.data, depth.data) << "depth of frame " << index;
    ASSERT_TRUE(f.right.data.empty());
  }
  // The stereo pair: the left camera on the trajectory, the right one a baseline along its x.
  {
    const size_t index = 7 % stereo.frameCount();
    const StampedPose& p = stereo.trajectory()[index];
    const double gain = exposureGain(so.image_noise, so.seed, p.t);
    Image left, right;
    left.channels = right.channels = 1;
    render(stereo.world(), stereo.camera(), p.pose, &buf, &left);
    Eigen::Isometry3d T_right = p.pose;
    T_right.translation() += p.pose.linear().col(0) * stereo.cameraInfo().baseline;
    render(stereo.world(), stereo.camera(), T_right, &buf, &right);
    applyImageNoise(so.image_noise, so.seed, index, 0, gain, &left);
    applyImageNoise(so.image_noise, so.seed, index, 1, gain, &right);
    stereo.render(index, &f);
    EXPECT_EQ(f.left.data, left.data);
    EXPECT_EQ(f.right.data, right.data);
    EXPECT_NE(left.data, right.data);  // the two cameras do not see the same image
    EXPECT_TRUE(f.depth.data.empty());
  }
  std::printf("[timing] VGA RGB-D frame (render + shading + noise + depth): %.2f ms\n", rgbd_ms);
  std::printf(
      "[timing]   visibility %.2f ms, shading %.2f ms, image noise %.2f ms, depth noise %.2f ms\n",
      vis, shade, inoise, dnoise);
  std::printf("[timing] KITTI 1241x376 stereo pair (two renders + noise): %.2f ms\n", stereo_ms);
  RecordProperty("rgbd_ms", std::to_string(rgbd_ms));
  RecordProperty("stereo_ms", std::to_string(stereo_ms));
}

}  // namespace
}  // namespace plugslam::sim::sim3d
