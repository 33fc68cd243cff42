// io.Ros2BagSource on ROS 2 bags made by independent implementations (tests/node/ros2_bags.js:
// @foxglove/rosbag, @foxglove/rosmsg2-serialization, @mcap/core, sql.js) from the DIS ROS 1 bag:
// every storage and compression gives the frames of io.RosbagSource on the ROS 1 bag, bit for
// bit; mounts come from /tf_static; every bad input is an error naming the file (and offset or
// topic) or a warning. Run by ctest as `io_ros2_bags` (tests/node/CMakeLists.txt), which makes the
// bags into a temporary folder and passes it as PLUGSLAM_ROS2_BAGS; skipped without it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>

#include "plugslam/errors.h"
#include "plugslam/mcap/reader.h"
#include "readers/cdr_messages.h"
#include "sources/ros2_bag_source.h"
#include "sources/rosbag_source.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace plugslam::io {
namespace {

namespace fs = std::filesystem;

std::string bagsDir() {
  const char* d = std::getenv("PLUGSLAM_ROS2_BAGS");
  return d ? d : "";
}

#define REQUIRE_BAGS()                                                                    \
  if (bagsDir().empty() || !fs::exists(fs::path(bagsDir()) / "bags.json"))                \
  GTEST_SKIP() << "no generated ROS 2 bags (PLUGSLAM_ROS2_BAGS; ctest's io_ros2_bags makes them)"

std::string bag(const std::string& name) {
  // bags.json's names are the files below (tests/node/ros2_bags.js).
  static const std::map<std::string, std::string> files = {
      {"mcap_none", "dis_none.mcap"},
      {"mcap_zstd", "dis_zstd.mcap"},
      {"mcap_unindexed_lz4", "dis_unindexed_lz4.mcap"},
      {"folder_mcap_lz4", "dis_lz4"},
      {"folder_db3", "dis_db3"},
      {"db3", "dis_db3/dis_db3_0.db3"},
      {"camera", "camera.mcap"}};
  return (fs::path(bagsDir()) / files.at(name)).string();
}

std::string disBag() {
  return plugslam::testing::dataDir() + "/laser2d/dis-underground-rosbag/dis-underground.bag";
}

std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}

struct Frames {
  std::vector<Frame> frames;
  std::size_t without_odometry = 0;
};

template <typename Source>
Frames readAll(Source& s) {
  Frames out;
  Frame f;
  while (s.next(f)) {
    out.frames.push_back(std::move(f));
    f = Frame{};
  }
  out.without_odometry = s.framesWithoutOdometry();
  return out;
}

void configureLikeTheRos1Config(BagSource& s, const std::string& path) {
  s.path = path;
  s.scans = std::vector<std::string>{"/scan:front_laser"};
  s.odometry = "/odom:odom";
  s.mounts = std::vector<double>{0.07, 0.0, 0.0};
  s.configure();
}

const Frames& ros1Frames() {
  static const Frames frames = [] {
    RosbagSource s;
    configureLikeTheRos1Config(s, disBag());
    return readAll(s);
  }();
  return frames;
}

TEST(Ros2Bags, EveryStorageAndCompressionGivesTheRos1Frames) {
  REQUIRE_BAGS();
  if (!fs::exists(disBag())) GTEST_SKIP() << "no data at " << disBag();
  const Frames& ros1 = ros1Frames();
  ASSERT_EQ(ros1.frames.size(), 4427u);
  for (const char* name :
       {"mcap_none", "mcap_zstd", "mcap_unindexed_lz4", "folder_mcap_lz4", "folder_db3", "db3"}) {
    SCOPED_TRACE(name);
    Ros2BagSource s;
    configureLikeTheRos1Config(s, bag(name));
    EXPECT_EQ(s.sizeHint(), 4427);
    const Frames ros2 = readAll(s);
    ASSERT_EQ(ros2.frames.size(), ros1.frames.size());
    EXPECT_EQ(ros2.without_odometry, ros1.without_odometry);
    size_t differing = 0;
    for (size_t i = 0; i < ros1.frames.size(); ++i) {
      const Frame& a = ros1.frames[i];
      const Frame& b = ros2.frames[i];
      const auto& sa = a.raw.get<LaserScan>("front_laser");
      const auto& sb = b.raw.get<LaserScan>("front_laser");
      const auto* oa = a.raw.find<Odometry2D>("odom");
      const auto* ob = b.raw.find<Odometry2D>("odom");
      // Exact: the same float32 ranges, the same stamps, the same interpolation.
      const bool same_ranges =
          sa.ranges.size() == sb.ranges.size() &&
          std::equal(sa.ranges.begin(), sa.ranges.end(), sb.ranges.begin(),
                     [](double x, double y) { return x == y || (std::isnan(x) && std::isnan(y)); });
      const bool same = a.stamp == b.stamp && same_ranges && sa.angle_min == sb.angle_min &&
                        sa.angle_increment == sb.angle_increment &&
                        sa.range_max == sb.range_max && sa.mount.matrix() == sb.mount.matrix() &&
                        (oa != nullptr) == (ob != nullptr) &&
                        (!oa || oa->pose.matrix() == ob->pose.matrix());
      if (!same) ++differing;
    }
    EXPECT_EQ(differing, 0u);
  }
}

TEST(Ros2Bags, MountsComeFromTfStaticWithoutMountsInTheConfig) {
  REQUIRE_BAGS();
  Ros2BagSource s;
  s.path = bag("mcap_zstd");
  s.configure();
  Frame f;
  ASSERT_TRUE(s.next(f));
  // The DIS bag's /tf: base_frame -> laser_frame = (0.0701905, -0.000201438, 0.00357746), no
  // rotation; the converter publishes that constant edge on /tf_static (float32 values).
  const auto& m = f.raw.get<LaserScan>("front_laser").mount;
  EXPECT_NEAR(m.translation().x(), 0.0701905, 1e-6);
  EXPECT_NEAR(m.translation().y(), -0.000201438, 1e-8);
  EXPECT_NEAR(std::atan2(m.linear()(1, 0), m.linear()(0, 0)), 0.0, 1e-12);
  // The ROS 1 source takes the same edge from the ROS 1 bag's /tf, where it never changes: the
  // same mount, bit for bit, so both configs run without `mounts` to the same trajectory.
  if (!fs::exists(disBag())) return;
  RosbagSource ros1;
  ros1.path = disBag();
  ros1.configure();
  Frame g;
  ASSERT_TRUE(ros1.next(g));
  EXPECT_EQ(g.raw.get<LaserScan>("front_laser").mount.matrix(), m.matrix());
}

TEST(Ros2Bags, AMissingScanTopicListsTheBagsTopics) {
  REQUIRE_BAGS();
  for (const char* name : {"mcap_none", "folder_db3"}) {
    Ros2BagSource s;
    s.path = bag(name);
    s.scans = std::vector<std::string>{"/front_scan:front_laser"};
    s.configure();
    Frame f;
    try {
      s.next(f);
      FAIL() << "no error";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("/front_scan"), std::string::npos) << what;
      EXPECT_NE(what.find("/scan (sensor_msgs/msg/LaserScan, 4427)"), std::string::npos) << what;
      EXPECT_NE(what.find(bag(name)), std::string::npos) << what;
    }
  }
}

TEST(Ros2Bags, ATopicOfAnotherTypeIsNamed) {
  REQUIRE_BAGS();
  Ros2BagSource s;
  s.path = bag("mcap_none");
  s.scans = std::vector<std::string>{"/odom:front_laser"};
  s.odometry = "";
  try {
    s.configure();
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/odom is nav_msgs/msg/Odometry, not "
                                         "sensor_msgs/msg/LaserScan"),
              std::string::npos)
        << e.what();
  }
}

TEST(Ros2Bags, AMissingOdometryTopicLeavesFramesWithoutOdometry) {
  REQUIRE_BAGS();
  Ros2BagSource s;
  s.path = bag("folder_mcap_lz4");
  s.odometry = "/wheel_odom:odom";
  s.configure();  // a warning names the topic
  const Frames got = readAll(s);
  EXPECT_EQ(got.frames.size(), 4427u);
  EXPECT_EQ(got.without_odometry, 4427u);
}

TEST(Ros2Bags, ACutMcapGivesTheFramesBeforeTheCut) {
  REQUIRE_BAGS();
  plugslam::testing::TempDir dir;
  for (const char* name : {"mcap_zstd", "mcap_unindexed_lz4"}) {
    const std::string bytes = slurp(bag(name));
    const std::string cut = dir.write(std::string(name) + "_cut.mcap",
                                      bytes.substr(0, bytes.size() * 6 / 10));
    Ros2BagSource s;
    s.path = cut;
    s.mounts = std::vector<double>{0.07, 0.0, 0.0};
    s.configure();
    const Frames got = readAll(s);
    // 60 % of the bytes: roughly 60 % of the scans (a warning gives the offset of the cut).
    EXPECT_GT(got.frames.size(), 4427u * 5 / 10) << name;
    EXPECT_LT(got.frames.size(), 4427u * 7 / 10) << name;
  }
}

// Offset of the first chunk's records (magic, header record, chunk prefix and fields).
size_t firstChunkRecords(const std::string& bytes) {
  auto le64 = [&](size_t at) {
    uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= uint64_t{static_cast<uint8_t>(bytes[at + k])} << (8 * k);
    return v;
  };
  size_t at = 8 + 9 + le64(9);
  EXPECT_EQ(bytes[at], 0x06);  // a chunk
  const size_t compression = le64(at + 9 + 28) & 0xFFFFFFFFu;
  return at + 9 + 28 + 4 + compression + 8;
}

void expectErrorNaming(const std::string& path, const std::string& words) {
  Ros2BagSource s;
  s.path = path;
  s.mounts = std::vector<double>{0.07, 0.0, 0.0};
  try {
    s.configure();
    readAll(s);
    FAIL() << "no error for " << path;
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

TEST(Ros2Bags, ABadChunkCrcNamesTheFileAndOffset) {
  REQUIRE_BAGS();
  plugslam::testing::TempDir dir;
  std::string bytes = slurp(bag("mcap_none"));
  bytes[firstChunkRecords(bytes) + 5000] ^= 0x10;
  expectErrorNaming(dir.write("crc.mcap", bytes), "CRC mismatch");
  expectErrorNaming(dir.file("crc.mcap"), "byte offset ");
}

TEST(Ros2Bags, AChunkThatDoesNotDecompressNamesTheFileAndOffset) {
  REQUIRE_BAGS();
  plugslam::testing::TempDir dir;
  std::string bytes = slurp(bag("mcap_zstd"));
  const size_t at = firstChunkRecords(bytes);
  for (size_t k = 0; k < 16; ++k) bytes[at + k] = static_cast<char>(0xA5);
  expectErrorNaming(dir.write("zstd.mcap", bytes), "does not decompress");
}

TEST(Ros2Bags, ADamagedDatabaseOrAMissingPathIsNamed) {
  REQUIRE_BAGS();
  plugslam::testing::TempDir dir;
  expectErrorNaming(dir.write("garbage.db3", std::string(4096, 'x')), "not a rosbag2 SQLite");
  expectErrorNaming(dir.file("nothing.mcap"), "does not exist");
  expectErrorNaming(dir.write("a.bag2", "x"), "not a ROS 2 bag");
}

TEST(Ros2Bags, AFolderWithoutMetadataIsReadByItsFiles) {
  REQUIRE_BAGS();
  plugslam::testing::TempDir dir;
  fs::copy_file(bag("mcap_zstd"), dir.path() / "rec_0.mcap");
  Ros2BagSource s;
  s.path = dir.path().string();
  s.mounts = std::vector<double>{0.07, 0.0, 0.0};
  s.configure();
  EXPECT_EQ(readAll(s).frames.size(), 4427u);
}

// The camera bag: messages of known values serialized by @foxglove/rosmsg2-serialization.
TEST(Ros2Bags, CameraMessagesDecodeToTheValuesWritten) {
  REQUIRE_BAGS();
  mcap::Reader r(bag("camera"));
  mcap::ReadMessage m;
  std::map<std::string, int> seen;
  while (r.next(m)) {
    ASSERT_NE(m.schema, nullptr);
    const auto* p = reinterpret_cast<const uint8_t*>(m.data.data());
    ++seen[m.schema->name];
    if (m.schema->name == kRos2Image) {
      ImageMsg img;
      decodeCdr(p, m.data.size(), img);
      EXPECT_EQ(img.header.stamp.sec, 1700000000u);
      EXPECT_EQ(img.header.stamp.nsec, 123456789u);
      EXPECT_EQ(img.header.frame_id, "camera_optical");
      EXPECT_EQ(img.width, 4u);
      EXPECT_EQ(img.height, 3u);
      EXPECT_EQ(img.encoding, "rgb8");
      EXPECT_EQ(img.step, 12u);
      ASSERT_EQ(img.data.size(), 36u);
      EXPECT_EQ(img.data[35], 35);
    } else if (m.schema->name == kRos2CompressedImage) {
      CompressedImageMsg img;
      decodeCdr(p, m.data.size(), img);
      EXPECT_EQ(img.format, "jpeg");
      EXPECT_EQ(img.data, (std::vector<uint8_t>{0xff, 0xd8, 0xff, 0xd9, 7}));
    } else if (m.schema->name == kRos2CameraInfo) {
      CameraInfoMsg info;
      decodeCdr(p, m.data.size(), info);
      EXPECT_EQ(info.distortion_model, "plumb_bob");
      EXPECT_EQ(info.d, (std::vector<double>{0.1, -0.2, 0.001, 0.002, 0.05}));
      EXPECT_EQ(info.k[2], 320.5);
      EXPECT_EQ(info.k[5], 240.25);
      EXPECT_EQ(info.p[3], -25.0);
      EXPECT_EQ(info.binning_y, 2u);
      EXPECT_EQ(info.roi, (std::array<uint32_t, 4>{5, 6, 7, 8}));
      EXPECT_TRUE(info.do_rectify);
    } else if (m.schema->name == kRos2TfMessage) {
      TfMsg tf;
      decodeCdr(p, m.data.size(), tf);
      ASSERT_EQ(tf.transforms.size(), 2u);
      EXPECT_EQ(tf.transforms[0].child_frame_id, "laser");
      EXPECT_EQ(tf.transforms[0].translation[0], 0.25);
      EXPECT_DOUBLE_EQ(tf.transforms[0].rotation[2], std::sin(0.25));  // JavaScript's sin
      EXPECT_EQ(tf.transforms[1].rotation[0], -0.5);
    }
  }
  EXPECT_EQ(seen.size(), 4u);
}

}  // namespace
}  // namespace plugslam::io
