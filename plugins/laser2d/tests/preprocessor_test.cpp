// ScanPreprocessor: beams -> robot-frame points with the mount, invalid beams, normals, filters.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "plugslam/errors.h"
#include "scan_preprocessor.h"
#include "synthetic.h"

namespace plugslam::laser2d {
namespace {

using test::Segment;

// `pre` configured with the settings the test gave it, then `scan` converted.
PointCloud2D configuredCloud(ScanPreprocessor& pre, const LaserScan& scan) {
  pre.configure();
  PointCloud2D cloud;
  pre.convert(scan, cloud);
  return cloud;
}

TEST(ScanPreprocessor, PointsOfAWallAreInTheRobotFrameWithPerpendicularNormals) {
  // A wall x = 3 in the robot frame, seen by a sensor mounted at (0.4, -0.2), rotated 0.3 rad.
  const std::vector<Segment> wall{{{3.0, -10.0}, {3.0, 10.0}}};
  test::ScanSpec spec;
  spec.beams = 181;
  spec.fov = M_PI;
  spec.mount = se2(0.4, -0.2, 0.3);
  const LaserScan scan = test::castScan(wall, SE2::Identity(), spec);

  ScanPreprocessor pre;
  const PointCloud2D cloud = configuredCloud(pre, scan);
  ASSERT_GT(cloud.size(), 100u);
  EXPECT_EQ(cloud.normals.size(), cloud.size());
  EXPECT_EQ(cloud.weights.size(), cloud.size());
  EXPECT_NEAR(cloud.sensor_origin.x(), 0.4, 1e-12);
  EXPECT_NEAR(cloud.sensor_origin.y(), -0.2, 1e-12);
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_NEAR(cloud.points[i].x(), 3.0, 1e-9) << "point " << i;
    EXPECT_NEAR(cloud.normals[i].norm(), 1.0, 1e-12);
    // Perpendicular to the wall and facing the sensor (which is at x < 3).
    EXPECT_NEAR(cloud.normals[i].x(), -1.0, 1e-9) << "normal " << i;
  }
}

TEST(ScanPreprocessor, AFarWallKeepsItsPointsWhenTheRadiusFollowsTheBeamSpacing) {
  // A wall x = 70 seen with 0.5 deg beams: neighbours are 0.61 m or more apart, so within the
  // fixed 0.5 m radius no point has the three a normal needs; with the radius grown to 2.5 beam
  // spacings the wall keeps its points.
  const std::vector<Segment> wall{{{70.0, -30.0}, {70.0, 30.0}}};
  test::ScanSpec spec;
  spec.beams = 81;
  spec.fov = 40 * M_PI / 180;
  spec.range_max = 80;
  const LaserScan scan = test::castScan(wall, SE2::Identity(), spec);
  ScanPreprocessor pre;
  pre.max_range = 80;
  pre.normal_spacing = 0;
  const PointCloud2D fixed = configuredCloud(pre, scan);
  EXPECT_EQ(fixed.size(), 0u);

  pre.normal_spacing = 2.5;
  const PointCloud2D adaptive = configuredCloud(pre, scan);
  EXPECT_GT(adaptive.size(), 75u);
  for (size_t i = 0; i < adaptive.size(); ++i) {
    EXPECT_NEAR(adaptive.points[i].x(), 70.0, 1e-9);
    EXPECT_NEAR(adaptive.normals[i].x(), -1.0, 1e-9) << "normal " << i;
  }
}

TEST(ScanPreprocessor, InvalidBeamsAreDropped) {
  LaserScan scan;
  scan.angle_min = -0.1;
  scan.angle_increment = 0.01;
  scan.range_min = 0.1;
  scan.range_max = 10.0;
  // 21 beams on a wall at distance ~2 (flat enough for normals), with holes punched in.
  for (int i = 0; i < 21; ++i) scan.ranges.push_back(2.0 / std::cos(scan.angle(i)));
  scan.ranges[3] = std::numeric_limits<double>::quiet_NaN();
  scan.ranges[7] = std::numeric_limits<double>::infinity();
  scan.ranges[10] = 0.05;  // below range_min
  scan.ranges[14] = 10.0;  // at range_max: no return
  scan.ranges[17] = -1.0;
  ScanPreprocessor pre;
  const PointCloud2D cloud = configuredCloud(pre, scan);
  EXPECT_EQ(cloud.size(), 16u);
  for (const auto& p : cloud.points) {
    EXPECT_TRUE(p.allFinite());
    EXPECT_NEAR(p.x(), 2.0, 1e-9);
  }

  // max_range and angle limits cut further.
  pre.max_range = 2.01;
  pre.min_angle = -0.05;
  pre.max_angle = 0.05;
  const PointCloud2D cut = configuredCloud(pre, scan);
  for (const auto& p : cut.points) EXPECT_LE(std::abs(std::atan2(p.y(), p.x())), 0.05 + 1e-9);
  EXPECT_LT(cut.size(), 11u);
  EXPECT_GT(cut.size(), 3u);
}

TEST(ScanPreprocessor, MountParameterOverridesTheScanMount) {
  const std::vector<Segment> wall{{{-10.0, 5.0}, {10.0, 5.0}}};
  test::ScanSpec spec;
  spec.beams = 91;
  spec.fov = M_PI / 2;
  spec.mount = se2(1.0, 0.0, M_PI / 2);  // true mount: looking along +y
  LaserScan scan = test::castScan(wall, SE2::Identity(), spec);
  scan.mount = SE2::Identity();  // the source does not know it

  ScanPreprocessor pre;
  pre.mount = std::vector<double>{1.0, 0.0, M_PI / 2};
  const PointCloud2D cloud = configuredCloud(pre, scan);
  ASSERT_GT(cloud.size(), 50u);
  for (size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_NEAR(cloud.points[i].y(), 5.0, 1e-9);
    EXPECT_NEAR(cloud.normals[i].y(), -1.0, 1e-9);
  }
}

TEST(ScanPreprocessor, ProcessWritesTheMeasurementEntry) {
  test::ScanSpec spec;
  Frame frame;
  frame.raw.set("laser", test::castScan(test::room(8, 6), se2(3, 2, 0.2), spec));
  ScanPreprocessor pre;
  pre.input = "laser";
  pre.output = "cue";
  pre.configure();
  EXPECT_TRUE(pre.process(frame));
  const PointCloud2D* cloud = frame.measurement.find<PointCloud2D>("cue");
  ASSERT_NE(cloud, nullptr);
  EXPECT_GT(cloud->size(), 300u);
  // A frame without the raw entry: the cue is absent.
  Frame empty;
  EXPECT_FALSE(pre.process(empty));
  EXPECT_FALSE(empty.measurement.has("cue"));
}

TEST(ScanPreprocessor, VoxelAndDecimationThinThePoints) {
  test::ScanSpec spec;
  const LaserScan scan = test::castScan(test::room(8, 6), se2(3, 2, 0.2), spec);
  ScanPreprocessor pre;
  pre.configure();
  PointCloud2D all, thin;
  pre.convert(scan, all);
  pre.voxel = 0.2;
  pre.convert(scan, thin);
  EXPECT_LT(thin.size(), all.size() / 2);
  for (size_t i = 1; i < thin.size(); ++i)
    EXPECT_GE((thin.points[i] - thin.points[i - 1]).norm(), 0.2 - 1e-9);
  pre.voxel = 0.0;
  pre.decimation = 3;
  pre.convert(scan, thin);
  EXPECT_NEAR(static_cast<double>(thin.size()), all.size() / 3.0, 0.05 * all.size());
}

TEST(ScanPreprocessor, BadParametersAreRejected) {
  ScanPreprocessor pre;
  pre.mount = std::vector<double>{1.0, 2.0};
  EXPECT_THROW(pre.configure(), ParamError);
  pre.mount = std::vector<double>{};
  pre.output = "front_laser";
  EXPECT_THROW(pre.configure(), ParamError);
  pre.output = "front";
  pre.min_angle = 1.0;
  pre.max_angle = 0.5;
  EXPECT_THROW(pre.configure(), ParamError);
}

}  // namespace
}  // namespace plugslam::laser2d
