// The io core logs through the shared libspdlog; this test links it only through that static
// library, so it does not get spdlog's compile definitions: without them the headers below
// would compile a registry of their own, and the log the test captures would not be the source's.
#ifndef SPDLOG_COMPILED_LIB
#define SPDLOG_COMPILED_LIB
#endif
#ifndef SPDLOG_SHARED_LIB
#define SPDLOG_SHARED_LIB
#endif
#include "sources/rosbag_source.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

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
std::string header(double t, const std::string& frame = "f") {
  return u32(0) + u32(sec(t)) + u32(nsec(t)) + str(frame);
}
// Three beams at -1, 0 and 1 rad, all `range` long; the scanner reaches 30 m.
std::string laserScan(double t, float range, const std::string& frame = "f") {
  std::string s = header(t, frame) + f32(-1.0f) + f32(1.0f) + f32(1.0f) + f32(0) + f32(0.1f) +
                  f32(0.1f) + f32(30.0f) + u32(3);
  for (int i = 0; i < 3; ++i) s += f32(range);
  return s + u32(0);
}
std::string odometry(double t, double x, double yaw, const std::string& child = "base_link") {
  std::string s = header(t) + str(child) + f64(x) + f64(2.0) + f64(0.0);
  s += f64(0) + f64(0) + f64(std::sin(yaw / 2)) + f64(std::cos(yaw / 2));
  for (int i = 0; i < 36 + 6 + 36; ++i) s += f64(0.0);
  return s;
}
// A geometry_msgs/TransformStamped: `child` at (x, y, z), turned by yaw about z, in `parent`.
std::string transform(double t, const std::string& parent, const std::string& child, double x,
                      double y, double z, double yaw) {
  return header(t, parent) + str(child) + f64(x) + f64(y) + f64(z) + f64(0) + f64(0) +
         f64(std::sin(yaw / 2)) + f64(std::cos(yaw / 2));
}
// A tf2_msgs/TFMessage of the given transforms.
std::string tfMessage(const std::vector<std::string>& transforms) {
  std::string s = u32(static_cast<std::uint32_t>(transforms.size()));
  for (const auto& t : transforms) s += t;
  return s;
}
// A bag of one uncompressed chunk holding `inner` (connections and messages), in this test
// process's own folder.
std::string writeBag(const std::string& name, const std::string& inner) {
  const std::string chunk = record(op(5) + field("compression", "none") +
                                       field("size", u32(static_cast<std::uint32_t>(inner.size()))),
                                   inner);
  const std::string bag_header =
      record(op(3) + field("index_pos", u64(0)) + field("conn_count", u32(0)) +
                 field("chunk_count", u32(0)),
             std::string(64, ' '));
  static const plugslam::testing::TempDir tmp;
  return tmp.write(name, "#ROSBAG V2.0\n" + bag_header + chunk);
}

std::string syntheticBag() {
  using namespace plugslam::io;
  std::string inner = connection(0, "/scan", kRosLaserScan.name, kRosLaserScan.md5) +
                      connection(1, "/rear", kRosLaserScan.name, kRosLaserScan.md5) +
                      connection(2, "/odom", kRosOdometry.name, kRosOdometry.md5);
  inner += message(2, 9.95, odometry(9.95, 0.0, 0.5));
  inner += message(0, 10.0, laserScan(10.0, 1.0f));
  inner += message(1, 10.02, laserScan(10.02, 2.0f));
  inner += message(2, 10.05, odometry(10.05, 1.0, 0.5));
  inner += message(0, 10.1, laserScan(10.1, 3.0f));
  inner += message(1, 10.13, laserScan(10.13, 4.0f));
  inner += message(0, 10.2, laserScan(10.2, 5.0f));
  inner += message(2, 10.25, odometry(10.25, 3.0, 0.5));
  inner += message(1, 10.31, laserScan(10.31, 6.0f));
  return writeBag("sync.bag", inner);
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

// The log lines of one test (the default logger's, at info and above).
class LogCapture {
 public:
  LogCapture() : sink_(std::make_shared<spdlog::sinks::ostream_sink_mt>(log_)) {
    spdlog::default_logger()->sinks().push_back(sink_);
  }
  ~LogCapture() {
    auto& sinks = spdlog::default_logger()->sinks();
    sinks.erase(std::remove(sinks.begin(), sinks.end(), sink_), sinks.end());
  }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;
  std::string text() const { return log_.str(); }
  std::size_t count(const std::string& what) const {
    std::size_t n = 0;
    const std::string t = text();
    for (auto at = t.find(what); at != std::string::npos; at = t.find(what, at + 1)) ++n;
    return n;
  }

 private:
  std::ostringstream log_;
  std::shared_ptr<spdlog::sinks::ostream_sink_mt> sink_;
};

// A robot whose scanner hangs from a bracket: base_link -> bracket (0.2, 0.1, 0.3 up, turned
// 0.5 rad) -> laser (0.05 ahead of the bracket, turned -0.2 rad). The laser in base_link:
Eigen::Isometry2d bracketMount() {
  return plugslam::se2(0.2, 0.1, 0.5) * plugslam::se2(0.05, 0.0, -0.2);
}

// Scans in frame /laser at 10.0, 10.1, 10.2 s and odometry moving base_link in odom, with the
// mount's two edges on `static_topic` (once, as ROS latches it) or on /tf with the odometry's
// edge (with every odometry message, as a ROS 1 robot publishes its fixed joints).
// With `laser_yaw_drift`, the laser turns on the bracket by that much at each /tf message.
std::string mountedBag(const std::string& name, bool on_tf_static, double laser_yaw_drift = 0) {
  using namespace plugslam::io;
  std::string inner = connection(0, "/scan", kRosLaserScan.name, kRosLaserScan.md5) +
                      connection(1, "/odom", kRosOdometry.name, kRosOdometry.md5) +
                      connection(2, "/tf", kRosTfMessage.name, kRosTfMessage.md5) +
                      connection(3, "/tf_static", kRosTfMessage.name, kRosTfMessage.md5);
  auto bracket = [](double t) {
    return transform(t, "/base_link", "/bracket", 0.2, 0.1, 0.3, 0.5);
  };
  auto laser = [](double t, double drift) {
    return transform(t, "bracket", "laser", 0.05, 0.0, 0.0, -0.2 + drift);
  };
  if (on_tf_static) inner += message(3, 9.9, tfMessage({bracket(9.9), laser(9.9, 0)}));
  for (int k = 0; k < 4; ++k) {
    const double t = 9.95 + 0.1 * k;
    inner += message(1, t, odometry(t, k, 0.1 * k));
    std::vector<std::string> edges{transform(t, "odom", "base_link", k, 2.0, 0.0, 0.1 * k)};
    if (!on_tf_static) {
      edges.push_back(bracket(t));
      edges.push_back(laser(t, k * laser_yaw_drift));
    }
    inner += message(2, t, tfMessage(edges));
    if (k < 3) inner += message(0, t + 0.05, laserScan(t + 0.05, 2.0f, "/laser"));
  }
  return writeBag(name, inner);
}

std::vector<Frame> readFrames(RosbagSource& source) {
  std::vector<Frame> frames;
  for (Frame f; source.next(f); f = Frame()) frames.push_back(f);
  return frames;
}

void expectMount(const Frame& f, const Eigen::Isometry2d& expected) {
  const auto& scan = f.raw.get<LaserScan>("front_laser");
  EXPECT_NEAR((scan.mount.translation() - expected.translation()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(plugslam::angleOf(scan.mount.linear() * expected.linear().transpose()), 0.0, 1e-12);
}

// Without `mounts` the scanner's mount is its frame's pose in the robot frame (the odometry's
// child frame) through /tf_static, said once; the scan comes out in the robot frame with it, and
// its range is the LaserScan's own.
TEST(RosbagSourceMounts, FromTfStatic) {
  LogCapture log;
  RosbagSource source;
  source.path = mountedBag("tf_static.bag", true);
  source.configure();
  const std::vector<Frame> frames = readFrames(source);
  ASSERT_EQ(frames.size(), 3u);
  for (const Frame& f : frames) expectMount(f, bracketMount());
  // The middle beam (0 rad, 2 m) in base_link: 2 m along the laser's x axis from its origin.
  const auto& scan = frames[0].raw.get<LaserScan>("front_laser");
  const Eigen::Vector2d beam = scan.mount * Eigen::Vector2d(scan.ranges[1], 0.0);
  EXPECT_NEAR((beam - bracketMount() * Eigen::Vector2d(2.0, 0.0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(beam.x(), 0.2 + 0.05 * std::cos(0.5) + 2.0 * std::cos(0.3), 1e-6);
  EXPECT_NEAR(beam.y(), 0.1 + 0.05 * std::sin(0.5) + 2.0 * std::sin(0.3), 1e-6);
  EXPECT_DOUBLE_EQ(scan.range_max, 30.0);
  EXPECT_EQ(log.count("mounted at"), 1u) << log.text();
  EXPECT_NE(log.text().find("[info]"), std::string::npos) << log.text();
  EXPECT_NE(log.text().find("base_link -> bracket (/tf_static) -> laser (/tf_static)"),
            std::string::npos)
      << log.text();
  EXPECT_EQ(log.text().find("[warning]"), std::string::npos) << log.text();
}

// A ROS 1 robot that publishes its fixed joints on /tf again and again: the edges that never
// change are the mount; the odometry's moving edge is not.
TEST(RosbagSourceMounts, FromTheConstantEdgesOfTf) {
  LogCapture log;
  RosbagSource source;
  source.path = mountedBag("tf.bag", false);
  source.configure();
  const std::vector<Frame> frames = readFrames(source);
  ASSERT_EQ(frames.size(), 3u);
  for (const Frame& f : frames) expectMount(f, bracketMount());
  EXPECT_NE(log.text().find("base_link -> bracket (/tf, the same in its 4 messages) -> laser "
                            "(/tf, the same in its 4 messages)"),
            std::string::npos)
      << log.text();
  EXPECT_EQ(log.text().find("[warning]"), std::string::npos) << log.text();
}

// An edge of /tf that moves is no mount: the laser is linked to nothing rigid, so it sits at the
// robot's origin, with a warning; likewise with no transforms at all.
TEST(RosbagSourceMounts, WithoutRigidTransformsTheIdentityWithAWarning) {
  for (const bool moving : {true, false}) {
    SCOPED_TRACE(moving ? "moving bracket" : "no transforms");
    LogCapture log;
    RosbagSource source;
    source.path = moving ? mountedBag("moving.bag", false, 0.01) : syntheticBag();
    source.configure();
    const std::vector<Frame> frames = readFrames(source);
    ASSERT_EQ(frames.size(), 3u);
    for (const Frame& f : frames) expectMount(f, Eigen::Isometry2d::Identity());
    EXPECT_EQ(log.count("[warning]"), 1u) << log.text();
    EXPECT_NE(log.text().find("mounted at the robot's origin"), std::string::npos) << log.text();
    EXPECT_NE(log.text().find(moving ? "link no frame 'laser' to the robot frame 'base_link'"
                                     : "the bag has no rigid transforms"),
              std::string::npos)
        << log.text();
  }
}

// `mounts` wins over the bag's transforms; it is said when they differ by more than the
// tolerance, and not when they agree within it.
TEST(RosbagSourceMounts, TheConfigWinsAndSaysWhenTheBagDisagrees) {
  const Eigen::Vector3d bag = plugslam::toVector(bracketMount());
  const double tol = RosbagSource::kMountTolerance;
  struct Case {
    Eigen::Vector3d mount;
    bool warned;
  };
  for (const Case& c : {Case{bag + Eigen::Vector3d(0.5 * tol, 0, 0), false},
                        Case{bag + Eigen::Vector3d(0, 0, -0.5 * tol), false},
                        Case{bag + Eigen::Vector3d(0, 2 * tol, 0), true},
                        Case{bag + Eigen::Vector3d(0, 0, 2 * tol), true},
                        Case{Eigen::Vector3d(0.3, 0, 0), true}}) {
    SCOPED_TRACE(c.mount.transpose());
    LogCapture log;
    RosbagSource source;
    source.path = mountedBag("tf_static.bag", true);
    source.mounts = std::vector<double>{c.mount.x(), c.mount.y(), c.mount.z()};
    source.configure();
    const std::vector<Frame> frames = readFrames(source);
    ASSERT_EQ(frames.size(), 3u);
    for (const Frame& f : frames) expectMount(f, plugslam::se2(c.mount));
    EXPECT_EQ(log.count("[warning]"), c.warned ? 1u : 0u) << log.text();
    if (c.warned) {
      EXPECT_NE(log.text().find("`mounts` (" + fmt::format("{:.4f}", c.mount.x())),
                std::string::npos)
          << log.text();
      EXPECT_NE(log.text().find("the bag's transforms say (0.2439, 0.1240, 0.3000)"),
                std::string::npos)
          << log.text();
    }
    EXPECT_EQ(log.text().find("mounted at"), std::string::npos) << log.text();
  }
}

// `base_frame` names the robot frame when the odometry does not; `tf_static` and `tf` empty read
// no transforms.
TEST(RosbagSourceMounts, BaseFrameAndTopicsAreParameters) {
  {
    RosbagSource source;
    source.path = mountedBag("tf_static.bag", true);
    source.odometry = std::string("");
    source.base_frame = std::string("/bracket");
    source.configure();
    const std::vector<Frame> frames = readFrames(source);
    ASSERT_EQ(frames.size(), 3u);
    expectMount(frames[0], plugslam::se2(0.05, 0.0, -0.2));
  }
  {
    LogCapture log;
    RosbagSource source;
    source.path = mountedBag("tf_static.bag", true);
    source.tf_static = std::string("");
    source.tf = std::string("");
    source.configure();
    const std::vector<Frame> frames = readFrames(source);
    ASSERT_EQ(frames.size(), 3u);
    expectMount(frames[0], Eigen::Isometry2d::Identity());
    EXPECT_NE(log.text().find("no transform topic is read"), std::string::npos) << log.text();
  }
}

// A transform topic that does not decode (another version of the message) stops a run that needs
// its mount, and only warns when `mounts` gives it.
TEST(RosbagSourceMounts, ATransformTopicThatDoesNotDecode) {
  using namespace plugslam::io;
  std::string inner = connection(0, "/scan", kRosLaserScan.name, kRosLaserScan.md5) +
                      connection(3, "/tf_static", kRosTfMessage.name, "0123456789abcdef");
  inner += message(3, 9.9, tfMessage({transform(9.9, "base_link", "laser", 0.2, 0, 0, 0)}));
  inner += message(0, 10.0, laserScan(10.0, 2.0f, "laser"));
  const std::string path = writeBag("bad_tf.bag", inner);
  {
    RosbagSource source;
    source.path = path;
    source.odometry = std::string("");
    source.configure();
    Frame f;
    try {
      source.next(f);
      FAIL() << "a mount from a transform topic that does not decode";
    } catch (const plugslam::ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("md5sum"), std::string::npos) << e.what();
    }
  }
  LogCapture log;
  RosbagSource source;
  source.path = path;
  source.odometry = std::string("");
  source.mounts = std::vector<double>{0.2, 0, 0};
  source.configure();
  const std::vector<Frame> frames = readFrames(source);
  ASSERT_EQ(frames.size(), 1u);
  expectMount(frames[0], plugslam::se2(0.2, 0, 0));
  EXPECT_NE(log.text().find("`mounts` not checked against the bag's transforms"),
            std::string::npos)
      << log.text();
}

// A TFMessage decodes field by field; a count its bytes cannot hold is refused before anything
// is allocated.
TEST(RosbagSourceMounts, TfMessagesDecode) {
  const std::string bytes = tfMessage({transform(3.5, "/base_link", "laser", 1, 2, 3, 0.5)});
  plugslam::io::TfMsg tf;
  plugslam::io::decodeTf(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), tf);
  ASSERT_EQ(tf.transforms.size(), 1u);
  const plugslam::io::TransformMsg& t = tf.transforms[0];
  EXPECT_EQ(t.header.frame_id, "/base_link");
  EXPECT_EQ(t.header.stamp.sec, 3u);
  EXPECT_EQ(t.child_frame_id, "laser");
  EXPECT_EQ(t.translation, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(t.rotation, (std::array<double, 4>{0, 0, std::sin(0.25), std::cos(0.25)}));
  const std::string lying = u32(1u << 30) + bytes.substr(4);
  EXPECT_THROW(plugslam::io::decodeTf(reinterpret_cast<const std::uint8_t*>(lying.data()),
                                      lying.size(), tf),
               plugslam::ParseError);
  EXPECT_THROW(plugslam::io::decodeTf(reinterpret_cast<const std::uint8_t*>(bytes.data()),
                                      bytes.size() - 1, tf),
               plugslam::ParseError);
}

// The DIS bag publishes its laser's mount on /tf with every odometry step: base_frame ->
// laser_frame = (0.0701905, -0.000201438), no rotation.
TEST(RosbagSourceData, DisBagMountFromItsTf) {
  if (!fs::exists(disBag())) GTEST_SKIP() << "no data at " << disBag() << " (set PLUGSLAM_DATA)";
  LogCapture log;
  RosbagSource source;
  source.path = disBag();
  source.configure();
  Frame f;
  ASSERT_TRUE(source.next(f));
  const auto& scan = f.raw.get<LaserScan>("front_laser");
  EXPECT_NEAR(scan.mount.translation().x(), 0.0701905, 1e-6);
  EXPECT_NEAR(scan.mount.translation().y(), -0.000201438, 1e-8);
  EXPECT_EQ(plugslam::angleOf(scan.mount.linear()), 0.0);
  EXPECT_DOUBLE_EQ(scan.range_max, 30.0);
  EXPECT_NE(log.text().find("base_frame -> laser_frame (/tf, the same in its 2999 messages)"),
            std::string::npos)
      << log.text();
}

}  // namespace
