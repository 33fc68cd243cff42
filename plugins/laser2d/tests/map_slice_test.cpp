// PointMapSlice: fusion keeps the map bounded on a static scene; clipping drops far points.
#include <gtest/gtest.h>

#include "point_map_slice.h"
#include "scan_preprocessor.h"
#include "synthetic.h"

namespace plugslam::laser2d {
namespace {

Frame frameAt(const std::vector<test::Segment>& world, const SE2& pose, uint32_t seed) {
  test::ScanSpec spec;
  spec.noise = 0.005;
  spec.seed = seed;
  ScanPreprocessor pre;
  pre.configure();
  Frame frame;
  frame.raw.set("front_laser", test::castScan(world, pose, spec));
  pre.process(frame);
  return frame;
}

TEST(PointMapSlice, FusionKeepsTheMapBoundedOnAStaticScene) {
  const auto world = test::room(8, 6);
  const SE2 pose = se2(3, 2, 0.3);
  PointMapSlice slice;
  slice.fusion_radius = 0.05;
  PropertyContainer scene;
  slice.merge(frameAt(world, pose, 1), scene, pose);
  const size_t first = scene.get<PointCloud2D>("front").size();
  ASSERT_GT(first, 300u);
  for (uint32_t k = 2; k <= 30; ++k) slice.merge(frameAt(world, pose, k), scene, pose);
  const auto& map = scene.get<PointCloud2D>("front");
  EXPECT_LT(map.size(), first * 13 / 10) << "first " << first;
  map.checkConsistent();
  double mean_weight = 0;
  for (double w : map.weights) mean_weight += w / map.size();
  EXPECT_GT(mean_weight, 10.0);
  // Fused points lie on the walls (noise averaged out) with unit normals.
  for (size_t i = 0; i < map.size(); ++i) {
    double d = 1e9;
    for (const auto& s : world) d = std::min(d, test::distanceToSegment(map.points[i], s));
    EXPECT_LT(d, 0.02);
    EXPECT_NEAR(map.normals[i].norm(), 1.0, 1e-9);
  }
}

TEST(PointMapSlice, PointsAreMergedAtTheRobotPose) {
  // The map frame is the world here: a robot at `pose` sees points that land on the walls.
  const auto world = test::room(8, 6);
  PointMapSlice slice;
  PropertyContainer scene;
  for (const SE2& pose : {se2(2, 2, 0.0), se2(5, 3, 1.2), se2(6, 1.5, -2.0)})
    slice.merge(frameAt(world, pose, 3), scene, pose);
  const auto& map = scene.get<PointCloud2D>("front");
  for (const auto& p : map.points) {
    double d = 1e9;
    for (const auto& s : world) d = std::min(d, test::distanceToSegment(p, s));
    EXPECT_LT(d, 0.03);
  }
}

TEST(PointMapSlice, ClippingDropsPointsFarFromTheRobot) {
  // A long corridor walked along x: with clipping the map keeps only the stretch near the robot.
  const auto world = test::corridor(-5.0, 60.0, 1.5);
  // One scan every metre from x = 0 to 50, merged into `map`.
  const auto walk = [&](PointMapSlice& s, PropertyContainer& map) {
    for (int k = 0; k <= 50; ++k) {
      const SE2 pose = se2(k, 0.0, 0.0);
      s.merge(frameAt(world, pose, k + 1), map, pose);
    }
  };
  PointMapSlice slice;
  slice.clip_radius = 8.0;
  PropertyContainer scene;
  walk(slice, scene);
  const auto& map = scene.get<PointCloud2D>("front");
  ASSERT_GT(map.size(), 100u);
  for (const auto& p : map.points) EXPECT_LE((p - Eigen::Vector2d(50, 0)).norm(), 8.0 + 1e-9);
  // Without clipping the whole corridor stays.
  PointMapSlice keep;
  keep.clip_radius = 0.0;
  PropertyContainer all;
  walk(keep, all);
  EXPECT_GT(all.get<PointCloud2D>("front").size(), 3 * map.size());
}

TEST(PointMapSlice, OppositeSidesOfAThinWallAreNotFused) {
  const std::vector<test::Segment> wall{{{3.0, -5.0}, {3.0, 5.0}}};
  PointMapSlice slice;
  PropertyContainer scene;
  slice.merge(frameAt(wall, se2(0, 0, 0), 1), scene, se2(0, 0, 0));
  const size_t one_side = scene.get<PointCloud2D>("front").size();
  slice.merge(frameAt(wall, se2(6, 0, M_PI), 2), scene, se2(6, 0, M_PI));
  EXPECT_GT(scene.get<PointCloud2D>("front").size(), one_side * 3 / 2);
}

}  // namespace
}  // namespace plugslam::laser2d
