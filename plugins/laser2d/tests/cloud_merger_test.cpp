// CloudMerger: a neighbour's clouds are moved into the target's frame and appended.
#include "cloud_merger.h"

#include <gtest/gtest.h>

#include <cmath>

#include "point_cloud2d.h"

using namespace plugslam;
using namespace plugslam::laser2d;

TEST(CloudMerger, MovesAndAppendsCloudsOfTheSameName) {
  PointCloud2D mine, theirs;
  mine.push({1, 0}, {1, 0}, 3.0);
  mine.sensor_origin = {0.5, 0.5};
  mine.touch();
  theirs.push({1, 0}, {0, 1}, 2.0);
  theirs.push({30, 0}, {1, 0}, 1.0);
  PropertyContainer into, from;
  into.set("front", mine);
  from.set("front", theirs);
  from.set("rear", theirs);
  from.set("label", std::string("not a cloud"));
  const uint64_t before = into.get<PointCloud2D>("front").revision;

  CloudMerger merger;
  merger.max_range = 10.0;
  merger.configure();
  // `from`'s frame is 2 m ahead of `into`'s and turned a quarter left.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(2, 0, 0);
  pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  merger.append(into, from, pose);

  const auto& front = into.get<PointCloud2D>("front");
  ASSERT_EQ(front.size(), 2u);  // the point 30 m from its origin is beyond max_range
  EXPECT_LT((front.points[1] - Eigen::Vector2d(2, 1)).norm(), 1e-12);
  EXPECT_LT((front.normals[1] - Eigen::Vector2d(-1, 0)).norm(), 1e-12);
  EXPECT_EQ(front.weights[1], 2.0);
  EXPECT_EQ(front.sensor_origin, Eigen::Vector2d(0.5, 0.5));  // the target's own
  EXPECT_NE(front.revision, before);  // search indexes of the old cloud must not be reused
  // A cloud the target lacks is added; other cues are left alone.
  ASSERT_NE(into.find<PointCloud2D>("rear"), nullptr);
  EXPECT_EQ(into.get<PointCloud2D>("rear").size(), 1u);
  EXPECT_FALSE(into.has("label"));
}
