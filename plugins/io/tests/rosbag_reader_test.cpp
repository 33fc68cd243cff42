#include "readers/rosbag_reader.h"

#include <bzlib.h>
#include <gtest/gtest.h>
#include <lz4frame.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>
#include <optional>

#include "plugslam/errors.h"
#include "readers/ros_messages.h"

namespace fs = std::filesystem;
using plugslam::InputError;
using plugslam::ParseError;
using namespace plugslam::io;  // test file only

#include "bag_bytes.h"
#include "temp_dir_test.h"
#include "test_paths.h"

namespace {

using namespace plugslam::io::bagbytes;  // test file only

std::string message(std::uint32_t conn, std::uint32_t sec, std::uint32_t nsec,
                    const std::string& data) {
  return record(op(2) + field("conn", u32(conn)) + field("time", u32(sec) + u32(nsec)), data);
}

std::string header(std::uint32_t seq, std::uint32_t sec, const std::string& frame) {
  return u32(seq) + u32(sec) + u32(500) + str(frame);
}
std::string laserScan(std::uint32_t seq, std::uint32_t sec, int beams) {
  std::string s = header(seq, sec, "/laser_frame");
  s += f32(-1.5f) + f32(1.5f) + f32(3.0f / (beams - 1)) + f32(0.001f) + f32(0.1f) + f32(0.1f) +
       f32(30.0f);
  s += u32(beams);
  for (int i = 0; i < beams; ++i) s += f32(i == 1 ? NAN : 1.0f + i);
  s += u32(0);
  return s;
}
std::string odometry(std::uint32_t seq, std::uint32_t sec, double x) {
  std::string s = header(seq, sec, "/odom") + str("/base_link");
  s += f64(x) + f64(2.0) + f64(0.0);
  double yaw = 0.5;
  s += f64(0) + f64(0) + f64(std::sin(yaw / 2)) + f64(std::cos(yaw / 2));
  for (int i = 0; i < 36; ++i) s += f64(i == 0 ? 0.01 : 0.0);
  s += f64(0.3) + f64(0) + f64(0) + f64(0) + f64(0) + f64(0.1);
  for (int i = 0; i < 36; ++i) s += f64(0.0);
  return s;
}

std::string compress(const std::string& plain, const std::string& how) {
  if (how == "none") return plain;
  if (how == "bz2") {
    std::vector<char> out(plain.size() + plain.size() / 100 + 600);
    unsigned n = static_cast<unsigned>(out.size());
    EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(plain.data()),
                                       static_cast<unsigned>(plain.size()), 9, 0, 0),
              BZ_OK);
    return std::string(out.data(), n);
  }
  // The frame parameters rosbag's roslz4 writes: independent 1 MB blocks, content checksum.
  LZ4F_preferences_t prefs;
  std::memset(&prefs, 0, sizeof prefs);
  prefs.frameInfo.blockSizeID = LZ4F_max1MB;
  prefs.frameInfo.blockMode = LZ4F_blockIndependent;
  prefs.frameInfo.contentChecksumFlag = LZ4F_contentChecksumEnabled;
  std::vector<char> out(LZ4F_compressFrameBound(plain.size(), &prefs));
  std::size_t n = LZ4F_compressFrame(out.data(), out.size(), plain.data(), plain.size(), &prefs);
  EXPECT_FALSE(LZ4F_isError(n));
  return std::string(out.data(), n);
}

std::string chunk(const std::string& inner, const std::string& how) {
  return record(op(5) + field("compression", how) +
                    field("size", u32(static_cast<std::uint32_t>(inner.size()))),
                compress(inner, how));
}

std::string bagHeader() {
  return record(op(3) + field("index_pos", u64(0)) + field("conn_count", u32(0)) +
                    field("chunk_count", u32(0)),
                std::string(64, ' '));
}

const char* kMagic = "#ROSBAG V2.0\n";

class RosbagReaderTest : public plugslam::testing::TempDirTest {
 protected:
  RosbagReaderTest() : TempDirTest("plugslam_rosbag") {}
  // A bag with /scan (conn 0) and /odom (conn 1) messages split over two chunks.
  std::string smallBag(const std::string& how) {
    std::string c1 = connection(0, "/scan", kRosLaserScan.name, kRosLaserScan.md5) +
                     connection(1, "/odom", kRosOdometry.name, kRosOdometry.md5) +
                     message(0, 100, 0, laserScan(1, 100, 5)) +
                     message(1, 100, 200, odometry(7, 100, 1.0)) +
                     message(0, 101, 0, laserScan(2, 101, 5));
    std::string c2 =
        message(1, 101, 500, odometry(8, 101, 1.5)) + message(0, 102, 0, laserScan(3, 102, 5));
    std::string index =
        record(op(4) + field("ver", u32(1)) + field("conn", u32(0)) + field("count", u32(0)), "");
    return kMagic + bagHeader() + chunk(c1, how) + index + chunk(c2, how) +
           connection(0, "/scan", kRosLaserScan.name, kRosLaserScan.md5);
  }
};

TEST_F(RosbagReaderTest, ReadsScansAndOdometryInEveryCompression) {
  for (const char* how : {"none", "bz2", "lz4"}) {
    SCOPED_TRACE(how);
    RosbagReader bag(write(std::string("b_") + how + ".bag", smallBag(how)));
    RosbagMessage m;
    std::vector<std::string> topics;
    std::vector<double> times;
    LaserScanMsg scan;
    OdometryMsg odom;
    while (bag.next(m)) {
      topics.push_back(m.connection->topic);
      times.push_back(m.time.toSec());
      EXPECT_FALSE(m.out_of_order);
      if (m.connection->topic == "/scan") {
        decodeLaserScan(bag, m, scan);
        EXPECT_EQ(scan.header.frame_id, "/laser_frame");
        ASSERT_EQ(scan.ranges.size(), 5u);
        EXPECT_DOUBLE_EQ(scan.ranges[0], 1.0);
        EXPECT_TRUE(std::isnan(scan.ranges[1]));
        EXPECT_DOUBLE_EQ(scan.ranges[4], 5.0);
        EXPECT_DOUBLE_EQ(scan.angle_min, -1.5);
        EXPECT_DOUBLE_EQ(scan.angle_increment, 0.75);
        EXPECT_DOUBLE_EQ(scan.range_max, 30.0);
        EXPECT_TRUE(scan.intensities.empty());
        EXPECT_EQ(scan.header.stamp.sec, m.time.sec);
        EXPECT_EQ(scan.header.stamp.nsec, 500u);
      } else {
        decodeOdometry(bag, m, odom);
        EXPECT_EQ(odom.header.frame_id, "/odom");
        EXPECT_EQ(odom.child_frame_id, "/base_link");
        EXPECT_DOUBLE_EQ(odom.position[1], 2.0);
        EXPECT_NEAR(odom.yaw(), 0.5, 1e-12);
        EXPECT_DOUBLE_EQ(odom.pose_covariance[0], 0.01);
        EXPECT_DOUBLE_EQ(odom.linear[0], 0.3);
        EXPECT_DOUBLE_EQ(odom.angular[2], 0.1);
      }
    }
    EXPECT_EQ(topics, (std::vector<std::string>{"/scan", "/odom", "/scan", "/odom", "/scan"}));
    EXPECT_TRUE(std::is_sorted(times.begin(), times.end()));
    EXPECT_EQ(bag.stats().chunks, 2u);
    EXPECT_EQ(bag.stats().compression.at(how), 2u);
    EXPECT_EQ(bag.stats().messages, 5u);
  }
}

TEST_F(RosbagReaderTest, TopicFilterAndSummary) {
  std::string p = write("b.bag", smallBag("bz2"));
  RosbagReaderOptions opt;
  opt.topics = {"/odom"};
  RosbagReader bag(p, opt);
  RosbagMessage m;
  int n = 0;
  while (bag.next(m)) {
    EXPECT_EQ(m.connection->topic, "/odom");
    ++n;
  }
  EXPECT_EQ(n, 2);
  EXPECT_EQ(bag.stats().filtered, 3u);
  auto topics = summarizeRosbag(p);
  ASSERT_EQ(topics.size(), 2u);
  EXPECT_EQ(topics[0].topic, "/odom");
  EXPECT_EQ(topics[0].type, kRosOdometry.name);
  EXPECT_EQ(topics[0].count, 2u);
  EXPECT_EQ(topics[1].topic, "/scan");
  EXPECT_EQ(topics[1].count, 3u);
  EXPECT_DOUBLE_EQ(topics[1].first_time, 100.0);
  EXPECT_DOUBLE_EQ(topics[1].last_time, 102.0);
}

TEST_F(RosbagReaderTest, SortsInterleavedChunksAndFlagsLateMessages) {
  std::string conns = connection(0, "/odom", kRosOdometry.name, kRosOdometry.md5);
  std::string a = conns + message(0, 5, 0, odometry(0, 5, 5)) +
                  message(0, 1, 0, odometry(0, 1, 1)) + message(0, 3, 0, odometry(0, 3, 3));
  std::string b = message(0, 2, 0, odometry(0, 2, 2)) + message(0, 6, 0, odometry(0, 6, 6)) +
                  message(0, 4, 0, odometry(0, 4, 4));
  std::string late = message(0, 0, 5, odometry(0, 0, 0));
  RosbagReader bag(write(
      "i.bag", kMagic + bagHeader() + chunk(a, "lz4") + chunk(b, "none") + chunk(late, "bz2")));
  RosbagMessage m;
  std::vector<std::uint32_t> in_order, flagged;
  while (bag.next(m)) (m.out_of_order ? flagged : in_order).push_back(m.time.sec);
  // The first two chunks overlap in time and come out merged; the last chunk's message is
  // earlier than messages already returned, so it is returned flagged.
  EXPECT_EQ(in_order, (std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(flagged, (std::vector<std::uint32_t>{0}));
  EXPECT_EQ(bag.stats().out_of_order, 1u);
}

TEST_F(RosbagReaderTest, MissingFileNotABagAndWrongVersion) {
  std::string missing = (dir_ / "none.bag").string();
  try {
    RosbagReader bag(missing);
    FAIL();
  } catch (const ParseError&) {
    FAIL() << "a missing file is not a parse error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  EXPECT_THROW(RosbagReader(write("x.bag", "hello world, not a bag at all")), ParseError);
  EXPECT_THROW(RosbagReader(dir_.string()), InputError);
  EXPECT_THROW(RosbagReader(write("e.bag", "")), ParseError);
  try {
    RosbagReader bag(write("v.bag", "#ROSBAG V1.2\nxxxx"));
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(e.message().find("V2.0"), std::string::npos) << e.message();
  }
}

// Every truncation point either ends cleanly at a record boundary or throws ParseError.
TEST_F(RosbagReaderTest, TruncatedBagsThrowWithByteOffset) {
  for (const char* how : {"none", "bz2", "lz4"}) {
    std::string full = smallBag(how);
    std::size_t errors = 0;
    std::size_t tried = 0;
    for (std::size_t cut = 13; cut < full.size(); cut += 3, ++tried) {
      try {
        auto bag = RosbagReader::fromBytes("t.bag", full.substr(0, cut));
        RosbagMessage m;
        while (bag->next(m)) {
        }
      } catch (const ParseError& e) {
        ++errors;
        EXPECT_EQ(e.line(), 0);
        EXPECT_NE(e.message().find("byte offset"), std::string::npos) << e.message();
      }
    }
    EXPECT_GT(errors, tried / 2) << how;
  }
}

TEST_F(RosbagReaderTest, CorruptBytesNeverCrash) {
  std::mt19937 rng(7);
  for (const char* how : {"none", "bz2", "lz4"}) {
    std::string full = smallBag(how);
    int parse_errors = 0;
    for (int iter = 0; iter < 300; ++iter) {
      std::string bytes = full;
      int flips = 1 + static_cast<int>(rng() % 4);
      for (int k = 0; k < flips; ++k) {
        std::size_t at = 13 + rng() % (bytes.size() - 13);
        bytes[at] = static_cast<char>(rng() & 0xff);
      }
      try {
        auto bag = RosbagReader::fromBytes("c.bag", bytes);
        RosbagMessage m;
        LaserScanMsg scan;
        OdometryMsg odom;
        while (bag->next(m)) {
          if (m.connection->type == kRosLaserScan.name) decodeLaserScan(*bag, m, scan);
          if (m.connection->type == kRosOdometry.name) decodeOdometry(*bag, m, odom);
        }
      } catch (const ParseError&) {
        ++parse_errors;
      }
    }
    EXPECT_GT(parse_errors, 0) << how;
  }
}

TEST_F(RosbagReaderTest, LyingLengthsAreRejectedWithoutHugeAllocations) {
  // A chunk header claiming 2 GB of uncompressed data.
  std::string inner = connection(0, "/odom", kRosOdometry.name, kRosOdometry.md5) +
                      message(0, 1, 0, odometry(0, 1, 1));
  std::string lying = record(op(5) + field("compression", "bz2") + field("size", u32(0x7fffffff)),
                             compress(inner, "bz2"));
  try {
    RosbagReader bag(write("l.bag", kMagic + bagHeader() + lying));
    RosbagMessage m;
    bag.next(m);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(e.message().find("header says"), std::string::npos) << e.message();
  }
  // A compressed stream cut short inside a record whose own length is consistent.
  for (const char* how : {"bz2", "lz4"}) {
    std::string z = compress(inner, how);
    std::string cut = record(op(5) + field("compression", how) +
                                 field("size", u32(static_cast<std::uint32_t>(inner.size()))),
                             z.substr(0, z.size() / 2));
    try {
      RosbagReader bag(write("z.bag", kMagic + bagHeader() + cut));
      RosbagMessage m;
      bag.next(m);
      FAIL() << how;
    } catch (const ParseError& e) {
      EXPECT_NE(e.message().find(std::string("chunk (") + how), std::string::npos) << e.message();
    }
  }
  // A record header length far beyond the file.
  std::string huge = kMagic + u32(0xfffffff0) + "op=";
  EXPECT_THROW(
      {
        RosbagReader bag(write("h.bag", huge));
        RosbagMessage m;
        bag.next(m);
      },
      ParseError);
  // A LaserScan whose ranges count is 2^32-1.
  std::string scan = header(1, 1, "/l") + std::string(28, '\0') + u32(0xffffffff) + f32(1.0f);
  LaserScanMsg out;
  try {
    decodeLaserScan(reinterpret_cast<const std::uint8_t*>(scan.data()), scan.size(), out);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(e.message().find("ranges"), std::string::npos) << e.message();
  }
  // Trailing bytes mean another message type.
  std::string odom = odometry(1, 1, 1) + "xx";
  OdometryMsg o;
  EXPECT_THROW(decodeOdometry(reinterpret_cast<const std::uint8_t*>(odom.data()), odom.size(), o),
               ParseError);
}

TEST_F(RosbagReaderTest, WrongTypeOrUnknownConnection) {
  RosbagReader bag(write("b.bag", smallBag("none")));
  RosbagMessage m;
  ASSERT_TRUE(bag.next(m));
  OdometryMsg odom;
  try {
    decodeOdometry(bag, m, odom);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(e.message().find("expected nav_msgs/Odometry"), std::string::npos) << e.message();
  }
  std::string orphan = message(9, 1, 0, odometry(0, 1, 1));
  RosbagReader bad(write("o.bag", kMagic + bagHeader() + chunk(orphan, "none")));
  try {
    bad.next(m);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(e.message().find("connection 9"), std::string::npos) << e.message();
  }
  std::string other_md5 =
      connection(0, "/scan", kRosLaserScan.name, "0123") + message(0, 1, 0, laserScan(0, 1, 3));
  RosbagReader md5(write("m.bag", kMagic + bagHeader() + chunk(other_md5, "none")));
  ASSERT_TRUE(md5.next(m));
  LaserScanMsg scan;
  EXPECT_THROW(decodeLaserScan(md5, m, scan), ParseError);
}

TEST(RosbagReaderRealData, DisUndergroundBag) {
  const std::string root = plugslam::testing::dataDir();
  fs::path p = fs::path(root) / "laser2d/dis-underground-rosbag/dis-underground.bag";
  if (!fs::exists(p)) GTEST_SKIP() << p << " is absent";
  auto t0 = std::chrono::steady_clock::now();
  RosbagReaderOptions opt;
  opt.topics = {"/scan", "/odom"};
  RosbagReader bag(p.string(), opt);
  RosbagMessage m;
  LaserScanMsg scan;
  OdometryMsg odom;
  std::size_t scans = 0, odoms = 0, beams_ok = 0;
  double first = 0, last = 0, prev = 0;
  bool ordered = true;
  while (bag.next(m)) {
    double t = m.time.toSec();
    if (scans + odoms == 0) first = t;
    if (t < prev) ordered = false;
    prev = last = t;
    if (m.connection->topic == "/scan") {
      decodeLaserScan(bag, m, scan);
      ++scans;
      if (scan.ranges.size() == 721 && scan.header.frame_id == "/laser_frame") ++beams_ok;
    } else {
      decodeOdometry(bag, m, odom);
      ++odoms;
    }
  }
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "dis-underground.bag: %zu scans, %zu odometry, %.2f s of data, chunks %zu, "
      "filtered %zu, read+decoded in %.3f s\n",
      scans, odoms, last - first, bag.stats().chunks, bag.stats().filtered, secs);
  EXPECT_EQ(scans, 4427u);
  EXPECT_EQ(odoms, 5484u);
  EXPECT_EQ(beams_ok, scans);
  EXPECT_NEAR(last - first, 110.4, 0.15);
  EXPECT_TRUE(ordered);
  EXPECT_EQ(bag.stats().out_of_order, 0u);
  EXPECT_EQ(bag.stats().filtered, 5998u);  // /tf
  EXPECT_EQ(bag.stats().compression.count("bz2"), 1u);

  auto topics = summarizeRosbag(p.string());
  ASSERT_EQ(topics.size(), 3u);
  for (const auto& t : topics) {
    std::printf("  %-6s %-24s %zu\n", t.topic.c_str(), t.type.c_str(), t.count);
    if (t.topic == "/tf") {
      EXPECT_EQ(t.count, 5998u);
    }
  }
}

}  // namespace
