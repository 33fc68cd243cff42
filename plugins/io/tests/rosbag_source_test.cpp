#include "sources/rosbag_source.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "readers/ros_messages.h"
#include "readers/rosbag_reader.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using plugslam::Frame;
using plugslam::LaserScan;
using plugslam::Odometry2D;
using plugslam::io::RosbagSource;

#include "bag_bytes.h"
#include "temp_dir.h"

namespace {

// Minimal ROS bag v2.0 writer (uncompressed chunk) for synthetic synchronisation cases.
using namespace plugslam::io::bagbytes;  // test file only

std::uint32_t sec(double t) { return static_cast<std::uint32_t>(t); }
std::uint32_t nsec(double t) { return static_cast<std::uint32_t>(std::lround((t - sec(t)) * 1e9)); }
std::string message(std::uint32_t conn, double t, const std::string& data) {
  return record(op(2) + field("conn", u32(conn)) + field("time", u32(sec(t)) + u32(nsec(t))), data);
}
std::string header(double t) { return u32(0) + u32(sec(t)) + u32(nsec(t)) + str("f"); }
std::string laserScan(double t, float range) {
  std::string s = header(t) + f32(-1.0f) + f32(1.0f) + f32(1.0f) + f32(0) + f32(0.1f) + f32(0.1f) +
                  f32(30.0f) + u32(3);
  for (int i = 0; i < 3; ++i) s += f32(range);
  return s + u32(0);
}
std::string odometry(double t, double x, double yaw) {
  std::string s = header(t) + str("base_link") + f64(x) + f64(2.0) + f64(0.0);
  s += f64(0) + f64(0) + f64(std::sin(yaw / 2)) + f64(std::cos(yaw / 2));
  for (int i = 0; i < 36 + 6 + 36; ++i) s += f64(0.0);
  return s;
}
std::string syntheticBag() {
  using namespace plugslam::io;
  std::string inner = connection(0, "/scan", kLaserScanType, kLaserScanMd5) +
                      connection(1, "/rear", kLaserScanType, kLaserScanMd5) +
                      connection(2, "/odom", kOdometryType, kOdometryMd5);
  inner += message(2, 9.95, odometry(9.95, 0.0, 0.5));
  inner += message(0, 10.0, laserScan(10.0, 1.0f));
  inner += message(1, 10.02, laserScan(10.02, 2.0f));
  inner += message(2, 10.05, odometry(10.05, 1.0, 0.5));
  inner += message(0, 10.1, laserScan(10.1, 3.0f));
  inner += message(1, 10.13, laserScan(10.13, 4.0f));
  inner += message(0, 10.2, laserScan(10.2, 5.0f));
  inner += message(2, 10.25, odometry(10.25, 3.0, 0.5));
  inner += message(1, 10.31, laserScan(10.31, 6.0f));
  const std::string chunk = record(op(5) + field("compression", "none") +
                                       field("size", u32(static_cast<std::uint32_t>(inner.size()))),
                                   inner);
  const std::string bag_header =
      record(op(3) + field("index_pos", u64(0)) + field("conn_count", u32(0)) +
                 field("chunk_count", u32(0)),
             std::string(64, ' '));
  static const plugslam::testing::TempDir tmp;  // this test process's own folder
  return tmp.write("sync.bag", "#ROSBAG V2.0\n" + bag_header + chunk);
}

std::string disBag() {
  return plugslam::testing::dataDir() + "/laser2d/dis-underground-rosbag/dis-underground.bag";
}

TEST(RosbagSource, RequiresAPath) {
  RosbagSource source;
  try {
    source.configure();
    FAIL() << "configure() accepted an empty path";
  } catch (const plugslam::ParamError& e) {
    EXPECT_EQ(e.path(), "path");
  }
}

TEST(RosbagSource, TopicEntryPairsAreChecked) {
  RosbagSource source;
  source.path = std::string("/nonexistent.bag");
  source.scans = std::vector<std::string>{"/scan"};
  EXPECT_THROW(source.configure(), plugslam::ParamError);
  source.scans = std::vector<std::string>{"/scan:a", "/scan2:a"};
  EXPECT_THROW(source.configure(), plugslam::ParamError);
  source.scans = std::vector<std::string>{"/scan:a", "/rear:b"};
  source.mounts = std::vector<double>{0, 0, 0};
  EXPECT_THROW(source.configure(), plugslam::ParamError);
  source.mounts = std::vector<double>{};
  EXPECT_THROW(source.configure(), plugslam::InputError);  // the bag does not exist
}

// The DIS bag: one frame per /scan message, odometry interpolated between its neighbours.
TEST(RosbagSourceData, DisBagFramesAndInterpolatedOdometry) {
  if (!fs::exists(disBag())) GTEST_SKIP() << "no data at " << disBag() << " (set PLUGSLAM_DATA)";
  // Collect the raw odometry messages to check the interpolation against.
  std::vector<std::pair<double, Eigen::Vector3d>> odom;
  size_t scans = 0;
  {
    plugslam::io::RosbagReaderOptions options;
    options.topics = {"/odom", "/scan"};
    plugslam::io::RosbagReader bag(disBag(), options);
    plugslam::io::RosbagMessage m;
    while (bag.next(m)) {
      if (m.connection->topic == "/scan") {
        ++scans;
        continue;
      }
      plugslam::io::OdometryMsg o;
      plugslam::io::decodeOdometry(bag, m, o);
      odom.push_back({o.header.stamp.toSec(), {o.position[0], o.position[1], o.yaw()}});
    }
  }
  std::sort(odom.begin(), odom.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  ASSERT_EQ(scans, 4427u);

  RosbagSource source;
  source.path = disBag();
  source.configure();
  EXPECT_EQ(source.sizeHint(), 4427);
  Frame f;
  size_t frames = 0, with_odom = 0, checked = 0;
  double last = -1;
  while (source.next(f)) {
    ++frames;
    EXPECT_GE(f.stamp, last);
    last = f.stamp;
    const auto& scan = f.raw.get<LaserScan>("front_laser");
    ASSERT_FALSE(scan.ranges.empty());
    EXPECT_GT(scan.angle_increment, 0);
    const auto* o = f.raw.find<Odometry2D>("odom");
    if (!o) continue;
    ++with_odom;
    // The interpolated position lies on the segment between the bracketing messages.
    auto it = std::lower_bound(odom.begin(), odom.end(), f.stamp,
                               [](const auto& p, double t) { return p.first < t; });
    if (it == odom.begin() || it == odom.end() || it->first - (it - 1)->first > 0.5) continue;
    const auto& a = (it - 1)->second;
    const auto& b = it->second;
    const double alpha = (f.stamp - (it - 1)->first) / (it->first - (it - 1)->first);
    const Eigen::Vector2d expected = a.head<2>() + alpha * (b.head<2>() - a.head<2>());
    // Interpolation on SE2 bends the straight segment slightly when the robot turns.
    EXPECT_LT((o->pose.translation() - expected).norm(),
              1e-4 + 0.5 * std::abs(plugslam::normalizeAngle(b.z() - a.z())) *
                         (b.head<2>() - a.head<2>()).norm());
    ++checked;
  }
  EXPECT_EQ(frames, 4427u);
  EXPECT_EQ(with_odom + source.framesWithoutOdometry(), frames);
  EXPECT_GT(with_odom, frames * 95 / 100);
  EXPECT_GT(checked, frames * 9 / 10);
  RecordProperty("frames_with_odometry", static_cast<int>(with_odom));
}

TEST(RosbagSource, SynchronisesScansAndOdometry) {
  RosbagSource source;
  source.path = syntheticBag();
  source.scans = std::vector<std::string>{"/scan:front_laser", "/rear:rear_laser"};
  source.mounts = std::vector<double>{0.1, 0, 0, -0.1, 0, M_PI};
  source.configure();
  EXPECT_EQ(source.sizeHint(), 3);
  std::vector<Frame> frames;
  Frame f;
  while (source.next(f)) {
    frames.push_back(f);
    f = Frame();
  }
  ASSERT_EQ(frames.size(), 3u);
  const double stamps[] = {10.0, 10.1, 10.2};
  const double xs[] = {0.5, 1.5, 2.5};  // halfway, a quarter and three quarters between readings
  const double front[] = {1.0, 3.0, 5.0};
  for (size_t i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(frames[i].stamp, stamps[i], 1e-6);
    const auto& scan = frames[i].raw.get<LaserScan>("front_laser");
    EXPECT_DOUBLE_EQ(scan.ranges[0], front[i]);
    EXPECT_NEAR(scan.mount.translation().x(), 0.1, 1e-12);
    const auto& odom = frames[i].raw.get<Odometry2D>("odom");
    EXPECT_NEAR(odom.pose.translation().x(), xs[i], 1e-6);
    EXPECT_NEAR(odom.pose.translation().y(), 2.0, 1e-9);
    EXPECT_NEAR(plugslam::angleOf(odom.pose.linear()), 0.5, 1e-9);
    EXPECT_NEAR(odom.stamp, stamps[i], 1e-6);  // interpolated at the frame's time
  }
  // /rear: 10.02 pairs with 10.0, 10.13 with 10.1; 10.31 is too far from 10.2.
  EXPECT_DOUBLE_EQ(frames[0].raw.get<LaserScan>("rear_laser").ranges[0], 2.0);
  EXPECT_DOUBLE_EQ(frames[1].raw.get<LaserScan>("rear_laser").ranges[0], 4.0);
  EXPECT_FALSE(frames[2].raw.has("rear_laser"));
  EXPECT_NEAR(frames[0].raw.get<LaserScan>("rear_laser").mount.translation().x(), -0.1, 1e-12);
}

TEST(RosbagSource, RepeatReplaysWithIncreasingStamps) {
  RosbagSource source;
  source.path = syntheticBag();
  source.repeat = int64_t{2};
  source.configure();
  EXPECT_EQ(source.sizeHint(), 6);
  std::vector<Frame> frames;
  for (Frame f; source.next(f); f = Frame()) frames.push_back(f);
  ASSERT_EQ(frames.size(), 6u);
  EXPECT_EQ(source.replay(), 2);
  // The second pass starts one frame period (0.1 s) after the first pass's last frame.
  const double stamps[] = {10.0, 10.1, 10.2, 10.3, 10.4, 10.5};
  const double xs[] = {0.5, 1.5, 2.5};
  for (size_t i = 0; i < frames.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(frames[i].stamp, stamps[i], 1e-6);
    EXPECT_NEAR(frames[i].raw.get<LaserScan>("front_laser").stamp, stamps[i], 1e-6);
    EXPECT_NEAR(frames[i].raw.get<Odometry2D>("odom").pose.translation().x(), xs[i % 3], 1e-6);
  }
  RosbagSource endless;
  endless.path = syntheticBag();
  endless.repeat = int64_t{0};
  endless.configure();
  EXPECT_EQ(endless.sizeHint(), -1);
  Frame f;
  for (int i = 0; i < 30; ++i) ASSERT_TRUE(endless.next(f));
  EXPECT_EQ(endless.replay(), 10);
}

TEST(RosbagSource, MissingScanTopicListsTheBagsTopics) {
  RosbagSource source;
  source.path = syntheticBag();
  source.scans = std::vector<std::string>{"/scna:front_laser"};
  source.configure();
  Frame f;
  try {
    source.next(f);
    FAIL() << "a bag without the scan topic gave frames";
  } catch (const plugslam::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/scna"), std::string::npos) << what;
    EXPECT_NE(what.find("/scan (sensor_msgs/LaserScan, 3)"), std::string::npos) << what;
  }
}

// Odometry slower than max_odometry_gap is not interpolated: a frame gets the nearest reading
// within the gap, stamped with that reading's own time, so odometry.WheelOdometry can tell a
// reading taken again (and extrapolate it) from a new one (issue 20).
TEST(RosbagSource, TheNearestReadingKeepsItsOwnStamp) {
  RosbagSource source;
  source.path = syntheticBag();
  source.max_odometry_gap = 0.07;  // readings at 9.95, 10.05, 10.25: none are interpolated
  source.configure();
  std::vector<Frame> frames;
  for (Frame f; source.next(f); f = Frame()) frames.push_back(f);
  ASSERT_EQ(frames.size(), 3u);
  // 10.1: 10.05 is 0.05 s away, 10.25 too far; 10.2: 10.25 is 0.05 s away.
  const double stamps[] = {10.05, 10.25};
  const double xs[] = {1.0, 3.0};
  for (size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE(i);
    const auto& odom = frames[i + 1].raw.get<Odometry2D>("odom");
    EXPECT_NEAR(odom.stamp, stamps[i], 1e-6);
    EXPECT_NEAR(odom.pose.translation().x(), xs[i], 1e-9);
  }
  // 10.0 is 0.05 s from both 9.95 and 10.05: either reading, with its own stamp.
  const auto& first = frames[0].raw.get<Odometry2D>("odom");
  EXPECT_NEAR(first.pose.translation().x(), first.stamp < 10.0 ? 0.0 : 1.0, 1e-9);
  EXPECT_NE(first.stamp, frames[0].stamp);
}

TEST(RosbagSource, OdometryGapLeavesFramesWithout) {
  RosbagSource source;
  source.path = syntheticBag();
  source.max_odometry_gap = 0.01;
  source.configure();
  Frame f;
  size_t frames = 0;
  while (source.next(f)) ++frames;
  EXPECT_EQ(frames, 3u);
  EXPECT_EQ(source.framesWithoutOdometry(), 3u);
}

}  // namespace
