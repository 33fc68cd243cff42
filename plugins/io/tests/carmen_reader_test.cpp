#include "readers/carmen_reader.h"

#include <bzlib.h>
#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "plugslam/errors.h"
#include "temp_dir_test.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using plugslam::InputError;
using plugslam::ParseError;
using plugslam::io::CarmenReader;
using plugslam::io::CarmenReaderOptions;
using plugslam::io::CarmenRecord;
using plugslam::io::ErrorPolicy;
using plugslam::io::ReaderWarning;

namespace {

constexpr double kPi = 3.14159265358979323846;

class CarmenReaderTest : public plugslam::testing::TempDirTest {
 protected:
  CarmenReaderTest() : TempDirTest("plugslam_carmen") {}
  std::string writeGz(const std::string& name, const std::string& text) {
    std::string p = (dir_ / name).string();
    gzFile f = gzopen(p.c_str(), "wb");
    gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
    gzclose(f);
    return p;
  }
  // The bytes of `text` as one bzip2 stream, as bzip2(1) writes them.
  static std::string bz2(const std::string& text) {
    std::string out(text.size() + text.size() / 100 + 600, '\0');
    unsigned int size = static_cast<unsigned int>(out.size());
    std::string in = text;
    const int rc = BZ2_bzBuffToBuffCompress(out.data(), &size, in.data(),
                                            static_cast<unsigned int>(in.size()), 9, 0, 0);
    EXPECT_EQ(rc, BZ_OK);
    out.resize(size);
    return out;
  }
};

// A FLASER line with n beams, ranges 1..n/100 and the given pose/time.
std::string flaser(int n, double x, double t, const char* kind = "FLASER") {
  std::ostringstream s;
  s << kind << " " << n;
  for (int i = 0; i < n; ++i) s << " " << 1.0 + i * 0.01;
  s << " " << x << " 2 0.5 " << x << " 2 0.5 " << t << " host " << t << "\n";
  return s.str();
}

std::string odom(double x, double t) {
  std::ostringstream s;
  s << "ODOM " << x << " 0.5 0.1 0.3 0.05 0 " << t << " host " << t << "\n";
  return s.str();
}

// The ParseError reading the rest of `r` ends in; a test failure when it ends without one.
ParseError readUntilError(CarmenReader& r) {
  CarmenRecord rec;
  try {
    while (r.next(rec)) {
    }
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "expected ParseError";
  return ParseError("", 0, "");
}

std::vector<CarmenRecord> readAll(CarmenReader& r) {
  std::vector<CarmenRecord> out;
  CarmenRecord rec;
  while (r.next(rec)) out.push_back(rec);
  return out;
}

const char* kRobotLaser =
    "ROBOTLASER1 0 -1.5708 3.14159 0.0174533 81.9 0.01 0 5 1 2 3 4 5 2 10 20 "
    "1.1 2.2 0.3 1.0 2.0 0.3 0.25 0.1 0.55 0.2 0.33 12.5 host 12.6\n";

TEST_F(CarmenReaderTest, ReadsAllMessageKinds) {
  std::string text =
      "# message formats defined: PARAM ODOM FLASER\n"
      "PARAM robot_frontlaser_offset 0.25 nohost 0\n" +
      odom(1.0, 10.0) + flaser(181, 1.5, 10.5) + "NEFF 30\n" + kRobotLaser +
      flaser(180, 1.6, 13.0, "RLASER") + "\n";
  CarmenReader r(write("a.log", text));
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 4u);

  ASSERT_EQ(recs[0].kind, CarmenRecord::Kind::kOdometry);
  EXPECT_EQ(recs[0].line, 3u);
  EXPECT_DOUBLE_EQ(recs[0].odometry.pose.x, 1.0);
  EXPECT_DOUBLE_EQ(recs[0].odometry.pose.y, 0.5);
  EXPECT_DOUBLE_EQ(recs[0].odometry.pose.theta, 0.1);
  EXPECT_DOUBLE_EQ(recs[0].odometry.tv, 0.3);
  EXPECT_DOUBLE_EQ(recs[0].odometry.rv, 0.05);
  EXPECT_DOUBLE_EQ(recs[0].odometry.timestamp, 10.0);
  EXPECT_TRUE(recs[0].odometry.has_timestamp);

  const auto& f = recs[1].laser;
  ASSERT_EQ(recs[1].kind, CarmenRecord::Kind::kLaser);
  EXPECT_EQ(f.message, "FLASER");
  EXPECT_EQ(f.sensor, "front");
  ASSERT_EQ(f.ranges.size(), 181u);
  EXPECT_DOUBLE_EQ(f.ranges[0], 1.0);
  EXPECT_DOUBLE_EQ(f.ranges[180], 2.8);
  EXPECT_DOUBLE_EQ(f.angle_min, -kPi / 2);
  EXPECT_DOUBLE_EQ(f.angle_increment, kPi / 180);
  EXPECT_NEAR(f.angle_min + 180 * f.angle_increment, kPi / 2, 1e-12);
  EXPECT_DOUBLE_EQ(f.max_range, 80.0);
  EXPECT_DOUBLE_EQ(f.laser_pose.x, 1.5);
  EXPECT_DOUBLE_EQ(f.robot_pose.theta, 0.5);
  EXPECT_DOUBLE_EQ(f.timestamp, 10.5);
  EXPECT_EQ(f.host, "host");
  EXPECT_DOUBLE_EQ(f.forward_offset, 0.25);
  EXPECT_FALSE(f.fov_from_log);

  const auto& rl = recs[2].laser;
  EXPECT_EQ(rl.message, "ROBOTLASER1");
  EXPECT_EQ(rl.sensor, "front");
  EXPECT_DOUBLE_EQ(rl.angle_min, -1.5708);
  EXPECT_DOUBLE_EQ(rl.angle_increment, 0.0174533);
  EXPECT_DOUBLE_EQ(rl.max_range, 81.9);
  EXPECT_EQ(rl.ranges, (std::vector<double>{1, 2, 3, 4, 5}));
  EXPECT_EQ(rl.remissions, (std::vector<double>{10, 20}));
  EXPECT_DOUBLE_EQ(rl.laser_pose.x, 1.1);
  EXPECT_DOUBLE_EQ(rl.robot_pose.y, 2.0);
  EXPECT_DOUBLE_EQ(rl.tv, 0.25);
  EXPECT_DOUBLE_EQ(rl.rv, 0.1);
  EXPECT_DOUBLE_EQ(rl.timestamp, 12.5);
  EXPECT_DOUBLE_EQ(rl.logger_timestamp, 12.6);

  const auto& rr = recs[3].laser;
  EXPECT_EQ(rr.message, "RLASER");
  EXPECT_EQ(rr.sensor, "rear");
  EXPECT_EQ(rr.ranges.size(), 180u);
  EXPECT_DOUBLE_EQ(rr.angle_increment, kPi / 180);

  const auto& st = r.stats();
  EXPECT_EQ(st.lasers, 3u);
  EXPECT_EQ(st.odometry, 1u);
  EXPECT_EQ(st.params, 1u);
  EXPECT_EQ(st.unknown, 1u);
  EXPECT_EQ(st.kinds.at("NEFF"), 1u);
  EXPECT_EQ(st.comments, 2u);
  EXPECT_FALSE(st.compressed);
  EXPECT_EQ(r.params().at("robot_frontlaser_offset"), "0.25");
}

TEST_F(CarmenReaderTest, GzipGivesTheSameRecordsAsPlainText) {
  std::string text = odom(1.0, 1.0) + flaser(361, 2.0, 1.5) + odom(1.2, 2.0);
  CarmenReader plain(write("p.log", text));
  CarmenReader gz(writeGz("p.log.gz", text));
  auto a = readAll(plain);
  auto b = readAll(gz);
  EXPECT_TRUE(gz.stats().compressed);
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 3u);
  EXPECT_EQ(a[1].laser.ranges, b[1].laser.ranges);
  EXPECT_DOUBLE_EQ(b[1].laser.angle_increment, kPi / 360);
  EXPECT_DOUBLE_EQ(b[2].odometry.pose.x, 1.2);
}

TEST_F(CarmenReaderTest, Bzip2GivesTheSameRecordsAsPlainText) {
  std::string text = "PARAM robot_frontlaser_offset 0.25 nohost 0\n";
  for (int i = 0; i < 300; ++i) text += odom(0.01 * i, i + 1.0) + flaser(180, 0.01 * i, i + 1.5);
  // Published benchmark logs are .clf.bz2; the magic bytes decide, not the name.
  CarmenReader plain(write("p.clf", text));
  CarmenReader bz(write("p.clf.bz2", bz2(text)));
  CarmenReader misnamed(write("p.log", bz2(text)));
  const auto a = readAll(plain);
  const auto b = readAll(bz);
  const auto c = readAll(misnamed);
  EXPECT_EQ(bz.stats().compression, "bzip2");
  EXPECT_TRUE(bz.stats().compressed);
  EXPECT_EQ(misnamed.stats().compression, "bzip2");
  EXPECT_EQ(plain.stats().compression, "");
  ASSERT_EQ(a.size(), 600u);
  ASSERT_EQ(b.size(), a.size());
  ASSERT_EQ(c.size(), a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].line, b[i].line);
    EXPECT_EQ(static_cast<int>(a[i].kind), static_cast<int>(b[i].kind));
    EXPECT_EQ(a[i].laser.ranges, b[i].laser.ranges);
    EXPECT_EQ(a[i].laser.timestamp, b[i].laser.timestamp);
    EXPECT_EQ(a[i].odometry.timestamp, b[i].odometry.timestamp);
    EXPECT_EQ(a[i].odometry.pose.x, b[i].odometry.pose.x);
  }
  EXPECT_EQ(bz.params().at("robot_frontlaser_offset"), "0.25");
}

TEST_F(CarmenReaderTest, Bzip2ConcatenatedStreamsAndTruncation) {
  // pbzip2 (and `cat a.bz2 b.bz2`) write several streams back to back: one log.
  std::string first, second;
  for (int i = 0; i < 100; ++i) first += odom(i, i + 1.0) + flaser(180, i, i + 1.5);
  for (int i = 100; i < 200; ++i) second += odom(i, i + 1.0) + flaser(180, i, i + 1.5);
  CarmenReader joined(write("joined.clf.bz2", bz2(first) + bz2(second)));
  const auto all = readAll(joined);
  ASSERT_EQ(all.size(), 400u);
  EXPECT_DOUBLE_EQ(all.back().laser.timestamp, 199 + 1.5);
  EXPECT_EQ(all.back().line, 400u);

  std::string whole;
  for (int i = 0; i < 2000; ++i) whole += odom(i, i + 1.0) + flaser(180, i, i + 1.5);
  const std::string bytes = bz2(whole);
  const std::string cut = write("cut.clf.bz2", bytes.substr(0, bytes.size() / 2));
  {
    CarmenReader r(cut);
    const ParseError e = readUntilError(r);
    EXPECT_NE(e.message().find("bzip2 stream is corrupt or truncated"), std::string::npos)
        << e.message();
  }
  CarmenReaderOptions opt;
  opt.policy = ErrorPolicy::kSkip;
  CarmenReader r(cut, opt);
  const auto recs = readAll(r);
  EXPECT_TRUE(r.stats().truncated);
  EXPECT_LT(recs.size(), 4000u);
}

TEST_F(CarmenReaderTest, LaserParamsSetOldFormatAngles) {
  std::string text =
      "PARAM laser_front_laser_fov 100 nohost 0\n"
      "PARAM laser_front_laser_resolution 0.5 nohost 0\n" +
      flaser(201, 0.0, 1.0) + flaser(180, 0.0, 2.0, "RLASER");
  CarmenReaderOptions opt;
  opt.old_format_max_range = 30.0;
  opt.sensor_names["FLASER"] = "laser_a";
  CarmenReader r(write("p.log", text), opt);
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 2u);
  EXPECT_EQ(recs[0].laser.sensor, "laser_a");
  EXPECT_TRUE(recs[0].laser.fov_from_log);
  EXPECT_NEAR(recs[0].laser.angle_min, -50.0 * kPi / 180, 1e-12);
  EXPECT_NEAR(recs[0].laser.angle_increment, 0.5 * kPi / 180, 1e-12);
  EXPECT_DOUBLE_EQ(recs[0].laser.max_range, 30.0);
  // The rear laser has no PARAMs: CARMEN's guess.
  EXPECT_DOUBLE_EQ(recs[1].laser.angle_min, -kPi / 2);
  EXPECT_DOUBLE_EQ(recs[1].laser.angle_increment, kPi / 180);
}

TEST_F(CarmenReaderTest, EmitsParamsOnRequest) {
  CarmenReaderOptions opt;
  opt.emit_params = true;
  CarmenReader r(write("p.log", "PARAM robot_length 0.54 nohost 0\n" + odom(0, 1)), opt);
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 2u);
  EXPECT_EQ(recs[0].kind, CarmenRecord::Kind::kParam);
  EXPECT_EQ(recs[0].param.name, "robot_length");
  EXPECT_EQ(recs[0].param.value, "0.54");
}

TEST_F(CarmenReaderTest, NonNumericTokenIsAnErrorWithLineInStrictMode) {
  std::string text = odom(0, 1) + "ODOM 1 abc 0 0 0 0 2 host 2\n" + odom(2, 3);
  CarmenReader r(write("bad.log", text));
  CarmenRecord rec;
  ASSERT_TRUE(r.next(rec));
  const ParseError e = readUntilError(r);
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(e.message().find("'abc' is not a number"), std::string::npos) << e.what();
  EXPECT_NE(std::string(e.what()).find("bad.log:2"), std::string::npos) << e.what();
}

TEST_F(CarmenReaderTest, SkipPolicyWarnsWithLineAndContinues) {
  std::string text = odom(0, 1) + "ODOM 1 abc 0 0 0 0 2 host 2\n" + "FLASER 3 1 2\n" + odom(2, 3);
  CarmenReaderOptions opt;
  opt.policy = ErrorPolicy::kSkip;
  std::vector<ReaderWarning> warnings;
  opt.on_warning = [&](const ReaderWarning& w) { warnings.push_back(w); };
  CarmenReader r(write("bad.log", text), opt);
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 2u);
  EXPECT_DOUBLE_EQ(recs[1].odometry.pose.x, 2.0);
  EXPECT_EQ(recs[1].line, 4u);
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0].line, 2u);
  EXPECT_EQ(warnings[1].line, 3u);
  EXPECT_NE(warnings[1].message.find("found 4"), std::string::npos) << warnings[1].message;
  EXPECT_EQ(r.stats().malformed, 2u);
}

TEST_F(CarmenReaderTest, CountLargerThanTokensIsRejected) {
  CarmenReader r(write("c.log", "FLASER 500 1 2 3 0 0 0 0 0 0 1 h 1\n"));
  CarmenRecord rec;
  EXPECT_THROW(r.next(rec), ParseError);
}

TEST_F(CarmenReaderTest, HugeAndNegativeCountsNeverAllocate) {
  for (const char* line : {"FLASER 99999999999999 1 2\n", "FLASER 9223372036854775807 1\n",
                           "FLASER 99999999999999999999999 1\n", "FLASER -5 1 2 3\n",
                           "ROBOTLASER1 0 0 3 0.1 80 0 0 4000000000 1 2\n",
                           "ROBOTLASER1 0 0 3 0.1 80 0 0 1 5 4000000000 1 2\n"}) {
    SCOPED_TRACE(line);
    CarmenReader r(write("h.log", line));
    const ParseError e = readUntilError(r);
    EXPECT_EQ(e.line(), 1);
    EXPECT_TRUE(e.message().find("only") != std::string::npos ||
                e.message().find("non-negative integer") != std::string::npos)
        << e.message();
  }
}

TEST_F(CarmenReaderTest, TruncatedLastLineIsReported) {
  std::string full = flaser(180, 1.0, 1.0);
  std::string text = odom(0, 0.5) + full.substr(0, full.size() / 2);
  CarmenReader r(write("t.log", text));
  CarmenRecord rec;
  ASSERT_TRUE(r.next(rec));
  const ParseError e = readUntilError(r);
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(e.message().find("truncated"), std::string::npos) << e.message();
  CarmenReaderOptions opt;
  opt.policy = ErrorPolicy::kSkip;
  CarmenReader s(write("t2.log", text), opt);
  EXPECT_EQ(readAll(s).size(), 1u);
  EXPECT_EQ(s.stats().malformed, 1u);
  // A last line without newline whose tokens add up is kept, with a warning.
  std::vector<std::string> warnings;
  opt.on_warning = [&](const ReaderWarning& w) { warnings.push_back(w.message); };
  CarmenReader k(write("t3.log", odom(0, 0.5) + "ODOM 1 2 3 0 0 0 1.5 host 1."), opt);
  EXPECT_EQ(readAll(k).size(), 2u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("no newline"), std::string::npos);
}

TEST_F(CarmenReaderTest, NanAndInfRangesAreKeptAsNoReturn) {
  std::string text = "FLASER 5 1.5 nan inf -1 0 0 0 0 0 0 0 1 h 1\n";
  CarmenReader r(write("n.log", text));
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 1u);
  const auto& l = recs[0].laser;
  ASSERT_EQ(l.ranges.size(), 5u);
  EXPECT_TRUE(plugslam::io::isRangeReturn(l.ranges[0], l.max_range));
  EXPECT_TRUE(std::isnan(l.ranges[1]));
  EXPECT_TRUE(std::isinf(l.ranges[2]));
  for (int i = 1; i < 5; ++i) EXPECT_FALSE(plugslam::io::isRangeReturn(l.ranges[i], l.max_range));
  EXPECT_FALSE(plugslam::io::isRangeReturn(81.91, 80.0));
}

TEST_F(CarmenReaderTest, NonFinitePoseOrTimeIsMalformed) {
  for (const char* line : {"FLASER 2 1 1 nan 0 0 0 0 0 1 h 1\n", "ODOM 0 0 0 0 0 0 inf h 1\n"}) {
    CarmenReader r(write("n.log", line));
    CarmenRecord rec;
    EXPECT_THROW(r.next(rec), ParseError) << line;
  }
}

TEST_F(CarmenReaderTest, BackwardsTimestamps) {
  std::string text = odom(0, 5.0) + odom(1, 4.0) + odom(2, 0.0) + odom(3, 4.5) +
                     flaser(180, 0, 3.0);  // lasers are their own stream
  {
    CarmenReader r(write("b.log", text));
    CarmenRecord rec;
    ASSERT_TRUE(r.next(rec));
    const ParseError e = readUntilError(r);
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.message().find("backwards"), std::string::npos);
  }
  for (bool via_time_policy : {false, true}) {
    CarmenReaderOptions opt;
    if (via_time_policy) {
      opt.time_policy = ErrorPolicy::kSkip;
    } else {
      opt.policy = ErrorPolicy::kSkip;
    }
    int warnings = 0;
    opt.on_warning = [&](const ReaderWarning&) { ++warnings; };
    CarmenReader r(write("b.log", text), opt);
    auto recs = readAll(r);
    ASSERT_EQ(recs.size(), 5u);
    EXPECT_FALSE(recs[0].odometry.time_backwards);
    EXPECT_TRUE(recs[1].odometry.time_backwards);
    // A zero timestamp means "unknown" in CARMEN logs: not checked, not flagged.
    EXPECT_FALSE(recs[2].odometry.has_timestamp);
    EXPECT_FALSE(recs[2].odometry.time_backwards);
    EXPECT_FALSE(recs[3].odometry.time_backwards);
    EXPECT_FALSE(recs[4].laser.time_backwards);
    EXPECT_EQ(r.stats().time_backwards, 1u);
    EXPECT_EQ(warnings, 1);
  }
}

TEST_F(CarmenReaderTest, EmptyScansAreSkippedWithAWarning) {
  std::string text =
      "FLASER 0 0 0 0 0 0 0 1 h 1\n"
      "ROBOTLASER1 0 -1.57 3.14 0.01 80 0.01 0 0 0 0 0 0 0 0 0 0 0 0 0 0 2 h 2\n" +
      odom(0, 3);
  int warnings = 0;
  CarmenReaderOptions opt;
  opt.on_warning = [&](const ReaderWarning& w) {
    ++warnings;
    EXPECT_NE(w.message.find("zero beams"), std::string::npos);
  };
  CarmenReader r(write("e.log", text), opt);
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].kind, CarmenRecord::Kind::kOdometry);
  EXPECT_EQ(r.stats().empty_scans, 2u);
  EXPECT_EQ(warnings, 2);
}

TEST_F(CarmenReaderTest, BinaryGarbage) {
  std::mt19937 rng(42);
  std::string junk(20000, '\0');
  for (char& c : junk) c = static_cast<char>(rng() & 0xff);
  junk[0] = 'X';
  junk[1] = '\x01';
  std::string path = write("g.bin", junk);
  {
    CarmenReader r(path);
    CarmenRecord rec;
    EXPECT_THROW(r.next(rec), ParseError);
  }
  CarmenReaderOptions opt;
  opt.policy = ErrorPolicy::kSkip;
  CarmenReader r(path, opt);
  CarmenRecord rec;
  while (r.next(rec)) {
  }
  EXPECT_GT(r.stats().malformed, 0u);
  EXPECT_EQ(r.stats().lasers + r.stats().odometry, 0u);
}

TEST_F(CarmenReaderTest, OverlongLineIsRejected) {
  std::string text = std::string(5000, 'A') + "\n" + odom(0, 1);
  CarmenReaderOptions opt;
  opt.max_line_bytes = 1000;
  {
    CarmenReader r(write("l.log", text), opt);
    CarmenRecord rec;
    EXPECT_THROW(r.next(rec), ParseError);
  }
  opt.policy = ErrorPolicy::kSkip;
  CarmenReader r(write("l.log", text), opt);
  auto recs = readAll(r);
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].line, 2u);
  EXPECT_EQ(r.stats().malformed, 1u);
}

TEST_F(CarmenReaderTest, MissingFileNamesThePath) {
  std::string p = (dir_ / "does_not_exist.log").string();
  try {
    CarmenReader r(p);
    FAIL() << "expected InputError";
  } catch (const ParseError&) {
    FAIL() << "a missing file is not a parse error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

TEST_F(CarmenReaderTest, TruncatedGzip) {
  std::string text;
  for (int i = 0; i < 400; ++i) text += odom(i, i + 1.0) + flaser(180, i, i + 1.5);
  std::string full = writeGz("full.log.gz", text);
  std::ifstream in(full, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string cut = write("cut.log.gz", bytes.substr(0, bytes.size() / 2));
  {
    CarmenReader r(cut);
    const ParseError e = readUntilError(r);
    EXPECT_NE(e.message().find("gzip"), std::string::npos) << e.message();
  }
  CarmenReaderOptions opt;
  opt.policy = ErrorPolicy::kSkip;
  CarmenReader r(cut, opt);
  auto recs = readAll(r);
  EXPECT_TRUE(r.stats().truncated);
  EXPECT_GT(recs.size(), 100u);
  EXPECT_LT(recs.size(), 800u);
}

TEST_F(CarmenReaderTest, RobotLaserWithoutLoggerTimestampAndRawLaser) {
  std::string text =
      "ROBOTLASER2 0 -1.0 2.0 0.5 20 0.01 0 5 1 2 3 4 5 0 1 2 3 4 5 6 0 0 0 0 0 7.5 host\n"
      "RAWLASER1 4 -1.5 3.0 1.5 30 0.01 1 3 1 nan 3 3 7 8 9 8.0 host 8.0\n";
  auto r = CarmenReader::fromText("mem.log", text);
  auto recs = readAll(*r);
  ASSERT_EQ(recs.size(), 2u);
  EXPECT_EQ(recs[0].laser.sensor, "rear");
  EXPECT_DOUBLE_EQ(recs[0].laser.timestamp, 7.5);
  EXPECT_DOUBLE_EQ(recs[0].laser.logger_timestamp, 0.0);
  EXPECT_DOUBLE_EQ(recs[0].laser.laser_pose.x, 1.0);
  EXPECT_DOUBLE_EQ(recs[0].laser.robot_pose.theta, 6.0);
  EXPECT_EQ(recs[1].laser.message, "RAWLASER1");
  EXPECT_EQ(recs[1].laser.sensor, "raw1");
  EXPECT_FALSE(recs[1].laser.has_pose);
  EXPECT_EQ(recs[1].laser.laser_type, 4);
  EXPECT_EQ(recs[1].laser.remissions, (std::vector<double>{7, 8, 9}));
  EXPECT_TRUE(std::isnan(recs[1].laser.ranges[1]));
}

TEST_F(CarmenReaderTest, DirectoryIsAnInputError) {
  EXPECT_THROW(CarmenReader r(dir_.string()), InputError);
}

// Random byte edits of a valid log: the reader returns records or throws ParseError, nothing else.
TEST_F(CarmenReaderTest, MutatedLogsNeverCrash) {
  std::string base = "PARAM laser_front_laser_resolution 0.5 nohost 0\n" + odom(0, 1) +
                     flaser(20, 1, 1.5) + kRobotLaser +
                     "RAWLASER1 4 -1.5 3.0 1.5 30 0.01 1 2 1 2 1 7 8.0 h 8.0\n" + odom(1, 2);
  std::mt19937 rng(3);
  const char alphabet[] = "0123456789 .-+eEnaif\n\t#\x01\xff";
  std::size_t errors = 0, records = 0;
  for (int iter = 0; iter < 3000; ++iter) {
    std::string text = base;
    int edits = 1 + static_cast<int>(rng() % 6);
    for (int k = 0; k < edits; ++k) {
      std::size_t at = rng() % text.size();
      switch (rng() % 3) {
        case 0:
          text[at] = alphabet[rng() % (sizeof(alphabet) - 1)];
          break;
        case 1:
          text.erase(at, 1 + rng() % 8);
          break;
        default:
          text.insert(at, 1, alphabet[rng() % (sizeof(alphabet) - 1)]);
          break;
      }
      if (text.empty()) text = "x";
    }
    for (ErrorPolicy policy : {ErrorPolicy::kStrict, ErrorPolicy::kSkip}) {
      CarmenReaderOptions opt;
      opt.policy = policy;
      auto r = CarmenReader::fromText("fuzz.log", text, opt);
      try {
        CarmenRecord rec;
        while (r->next(rec)) {
          ++records;
          if (rec.kind == CarmenRecord::Kind::kLaser) {
            EXPECT_FALSE(rec.laser.ranges.empty());
          }
        }
      } catch (const ParseError& e) {
        ++errors;
        EXPECT_GT(e.line(), 0);
      }
    }
  }
  EXPECT_GT(errors, 0u);
  EXPECT_GT(records, 0u);
}

struct RealLog {
  const char* file;
  std::size_t lasers, odometry, params, beams;
};

TEST(CarmenReaderRealData, ReadsEveryLog) {
  const std::string root = plugslam::testing::dataDir();
  // Counts from the SOURCE.md of each log (computed there with awk).
  const RealLog logs[] = {
      {"laser2d/edmonton-gfs-corrected/edmonton-corrected.log.gz", 340, 6351, 21, 180},
      {"laser2d/freiburg-079-gfs-corrected/freiburg-079-corrected.log.gz", 4791, 9725, 187, 360},
      {"laser2d/freiburg-101-gfs-corrected/freiburg-101-corrected.log.gz", 292, 4569, 168, 360},
      {"laser2d/freiburg-campus-gfs-corrected/freiburg-campus-corrected.log.gz", 2008, 17691, 245,
       360},
      {"laser2d/intel-gfs-corrected/intel-corrected.log.gz", 910, 14541, 2, 180},
      {"laser2d/seattle-gfs-corrected/seattle-corrected.log.gz", 241, 19311, 0, 361},
      // The benchmark's original logs, bzip2 as published.
      {"laser2d/intel-kuemmerle-benchmark/intel.clf.bz2", 13631, 26915, 2, 180},
      {"laser2d/fr079-kuemmerle-benchmark/fr079.clf.bz2", 4934, 8951, 187, 360},
  };
  int found = 0;
  for (const auto& log : logs) {
    fs::path p = fs::path(root) / log.file;
    if (!fs::exists(p)) continue;
    ++found;
    CarmenReaderOptions opt;  // strict on malformed lines: the real logs have none
    opt.time_policy = ErrorPolicy::kSkip;
    auto t0 = std::chrono::steady_clock::now();
    CarmenReader r(p.string(), opt);
    CarmenRecord rec;
    std::size_t beams_ok = 0;
    std::optional<plugslam::io::CarmenLaser> first, last;
    double range_sum = 0;
    while (r.next(rec)) {
      if (rec.kind == CarmenRecord::Kind::kLaser) {
        if (rec.laser.ranges.size() == log.beams) ++beams_ok;
        EXPECT_EQ(rec.laser.sensor, "front");
        EXPECT_NEAR(rec.laser.angle_min, -kPi / 2, 1e-12);
        for (double range : rec.laser.ranges) range_sum += range;
        if (!first) first = rec.laser;
        last = rec.laser;
      }
    }
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& st = r.stats();
    std::printf("%-70s lasers %zu odom %zu params %zu unknown %zu backwards %zu  %.3f s\n",
                log.file, st.lasers, st.odometry, st.params, st.unknown, st.time_backwards, secs);
    EXPECT_EQ(st.lasers, log.lasers) << log.file;
    EXPECT_EQ(st.odometry, log.odometry) << log.file;
    EXPECT_EQ(st.params, log.params) << log.file;
    EXPECT_EQ(beams_ok, log.lasers) << log.file;
    EXPECT_EQ(st.malformed, 0u);
    EXPECT_EQ(st.unknown, st.kinds.count("NEFF") ? st.kinds.at("NEFF") : 0u);
    EXPECT_TRUE(st.compressed);
    if (std::string(log.file).find("intel-gfs") != std::string::npos && first) {
      // Values, not only counts (awk over the decompressed log); the time is printed, not
      // asserted: it measures the machine as much as the reader.
      EXPECT_DOUBLE_EQ(first->timestamp, 32.9068);
      EXPECT_DOUBLE_EQ(first->ranges.front(), 1.09);
      EXPECT_DOUBLE_EQ(first->laser_pose.x, 0.600266);
      EXPECT_DOUBLE_EQ(last->timestamp, 2683.77);
      EXPECT_DOUBLE_EQ(last->laser_pose.x, -0.596494);
      EXPECT_DOUBLE_EQ(last->laser_pose.y, -0.101202);
      EXPECT_DOUBLE_EQ(last->laser_pose.theta, 0.0119294);
      EXPECT_NEAR(range_sum, 792927.54, 1e-6);
    }
  }
  if (found == 0) GTEST_SKIP() << "no CARMEN log under " << root << "/laser2d";
}

}  // namespace
