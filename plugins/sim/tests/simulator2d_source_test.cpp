#include "simulator2d_source.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "source_frames.h"
#include "temp_dir.h"

using plugslam::Frame;
using plugslam::LaserScan;
using plugslam::Odometry2D;
using plugslam::sim::Simulator2DSource;

namespace {

std::vector<Frame> firstFrames(Simulator2DSource& source, size_t n) {
  std::vector<Frame> frames;
  Frame f;
  while (frames.size() < n && source.next(f)) {
    frames.push_back(f);
    f = Frame();
  }
  return frames;
}

TEST(Simulator2DSource, FramesHaveLasersOdometryAndGroundTruth) {
  Simulator2DSource source;
  source.session = std::string("stage-0");
  source.configure();
  ASSERT_GT(source.sizeHint(), 100);
  Frame f;
  EXPECT_EQ(plugslam::testing::readInOrder(source, f, [](const Frame&) {}), source.sizeHint());
  const auto& front = f.raw.get<LaserScan>("front_laser");
  const auto& rear = f.raw.get<LaserScan>("rear_laser");
  EXPECT_EQ(front.ranges.size(), 1081u);
  EXPECT_NEAR(front.mount.translation().x(), 0.2, 1e-12);
  EXPECT_NEAR(rear.mount.translation().x(), -0.2, 1e-12);
  EXPECT_NEAR(std::abs(plugslam::angleOf(rear.mount.linear())), M_PI, 1e-12);
  size_t returns = 0;
  for (size_t i = 0; i < front.ranges.size(); ++i) returns += front.isReturn(i);
  EXPECT_GT(returns, 500u);
  EXPECT_TRUE(f.raw.holds<Odometry2D>("odom"));
  EXPECT_TRUE(f.raw.holds<Eigen::Isometry2d>("ground_truth"));
  // The session is about as long as the seed's 43 m.
  EXPECT_NEAR(source.simulator().pathLength(), 43.2, 1.0);
}

TEST(Simulator2DSource, DeterministicBySeed) {
  auto run = [](int64_t seed) {
    Simulator2DSource source;
    source.session = std::string("stage-0");
    source.seed = seed;
    source.configure();
    return firstFrames(source, 30);
  };
  const auto a = run(7), b = run(7), c = run(8);
  ASSERT_EQ(a.size(), 30u);
  bool differs = false;
  for (size_t i = 0; i < a.size(); ++i) {
    const auto& ra = a[i].raw.get<LaserScan>("front_laser").ranges;
    const auto& rb = b[i].raw.get<LaserScan>("front_laser").ranges;
    const auto& rc = c[i].raw.get<LaserScan>("front_laser").ranges;
    for (size_t k = 0; k < ra.size(); ++k) {
      if (std::isnan(ra[k])) {
        EXPECT_TRUE(std::isnan(rb[k]));
      } else {
        EXPECT_EQ(ra[k], rb[k]);
      }
      differs |= !(ra[k] == rc[k]) && !(std::isnan(ra[k]) && std::isnan(rc[k]));
    }
    EXPECT_TRUE(
        a[i].raw.get<Odometry2D>("odom").pose.isApprox(b[i].raw.get<Odometry2D>("odom").pose, 0.0));
    // Ground truth does not depend on the seed in tour mode.
    EXPECT_TRUE(a[i].raw.get<Eigen::Isometry2d>("ground_truth")
                    .isApprox(c[i].raw.get<Eigen::Isometry2d>("ground_truth"), 1e-12));
  }
  EXPECT_TRUE(differs) << "another seed gives other noise";
}

TEST(Simulator2DSource, LaserSelectionAndNoiseSwitches) {
  Simulator2DSource source;
  source.session = std::string("stage-0");
  source.lasers = std::vector<std::string>{"front_laser"};
  source.odometry_noise = 0.0;
  source.range_noise = 0.0;
  source.dropout = 0.0;
  source.configure();
  const auto frames = firstFrames(source, 50);
  ASSERT_EQ(frames.size(), 50u);
  for (const auto& f : frames) {
    EXPECT_FALSE(f.raw.has("rear_laser"));
    EXPECT_TRUE(f.raw.has("front_laser"));
    // Perfect odometry starts at the ground truth and stays on it.
    const auto& odom = f.raw.get<Odometry2D>("odom").pose;
    const auto& gt = f.raw.get<Eigen::Isometry2d>("ground_truth");
    EXPECT_LT((odom.translation() - gt.translation()).norm(), 1e-9);
    EXPECT_LT(std::abs(plugslam::angleOf(odom.linear().transpose() * gt.linear())), 1e-9);
  }
}

TEST(Simulator2DSource, BadParametersAreParamErrors) {
  {
    Simulator2DSource source;
    source.lasers = std::vector<std::string>{"side_laser"};
    EXPECT_THROW(source.configure(), plugslam::ParamError);
  }
  {
    Simulator2DSource source;
    source.lasers = std::vector<std::string>{};
    EXPECT_THROW(source.configure(), plugslam::ParamError);
  }
  {
    Simulator2DSource source;
    source.world = std::string("/nonexistent.segments");
    EXPECT_THROW(source.configure(), plugslam::ParamError);  // no start place
    source.start = std::vector<double>{1.0, 1.0};
    EXPECT_THROW(source.configure(), plugslam::InputError);  // missing file
  }
  {
    Simulator2DSource source;
    EXPECT_THROW(source.session = std::string("stage-9"), plugslam::ValueError);
  }
}

}  // namespace

namespace {

TEST(Simulator2DSource, ExploresACustomSegmentWorld) {
  const plugslam::testing::TempDir tmp;
  const std::string path =
      tmp.write("room.segments",
                "# 12 x 8 m room with a pillar\n0 0 12 0\n12 0 12 8\n12 8 0 8\n0 8 0 0\n"
                "5 3 7 3\n7 3 7 5\n7 5 5 5\n5 5 5 3\n");
  auto run = [&](int64_t seed) {
    Simulator2DSource source;
    source.session = std::string("stage-0");
    source.world = path;
    source.start = std::vector<double>{2.0, 2.0};
    source.seed = seed;
    source.configure();
    EXPECT_NEAR(source.simulator().pathLength(), 43.2, 1.0);  // stage-0's length
    return source.simulator().groundTruth();
  };
  const auto a = run(1), b = run(1);
  ASSERT_GT(a.size(), 100u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a[i].isApprox(b[i], 0.0)) << i;
    EXPECT_GT(a[i].x(), 0.0);
    EXPECT_LT(a[i].x(), 12.0);
    EXPECT_GT(a[i].y(), 0.0);
    EXPECT_LT(a[i].y(), 8.0);
  }
  EXPECT_NEAR(a.front().x(), 2.0, 1e-9);
  EXPECT_NEAR(a.front().y(), 2.0, 1e-9);
}

}  // namespace
