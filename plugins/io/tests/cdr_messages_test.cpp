// The CDR decoders on messages laid out by hand from the XCDR1 rules (each primitive aligned to
// its size from the end of the 4-byte encapsulation header), both byte orders; every prefix of a
// message is a ParseError, never a crash. (@foxglove/rosmsg2-serialization's own bytes are
// decoded in ros2_bags_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "cdr_writer.h"
#include "plugslam/errors.h"
#include "readers/cdr_messages.h"

namespace plugslam::io {
namespace {

using Cdr = plugslam::testing::CdrWriter;

Cdr laserScan(bool little) {
  Cdr c(little);
  c.header(1510757286, 120767618, "laser_frame");
  for (float v : {-2.35619f, 2.35619f, 0.00654498f, 0.0f, 0.025f, 0.1f, 30.0f}) c.put<float>(v);
  c.put<uint32_t>(3).put<float>(1.5f).put<float>(std::nanf("")).put<float>(29.0f);
  c.put<uint32_t>(0);
  return c;
}

TEST(CdrMessages, LaserScanInBothByteOrders) {
  for (const bool little : {true, false}) {
    const Cdr c = laserScan(little);
    LaserScanMsg m;
    decodeCdr(c.bytes().data(), c.bytes().size(), m);
    EXPECT_EQ(m.header.stamp.sec, 1510757286u);
    EXPECT_EQ(m.header.stamp.nsec, 120767618u);
    EXPECT_EQ(m.header.frame_id, "laser_frame");
    EXPECT_FLOAT_EQ(m.angle_min, -2.35619f);
    EXPECT_FLOAT_EQ(m.angle_increment, 0.00654498f);
    EXPECT_FLOAT_EQ(m.range_max, 30.0f);
    ASSERT_EQ(m.ranges.size(), 3u);
    EXPECT_EQ(m.ranges[0], 1.5);
    EXPECT_TRUE(std::isnan(m.ranges[1]));
    EXPECT_TRUE(m.intensities.empty());
  }
}

TEST(CdrMessages, OdometryAlignsItsDoublesToEight) {
  Cdr c;
  c.header(7, 8, "odom").str("base_link");  // 4+4+4+5 + 4+10 = 31 bytes: padding before doubles
  for (int i = 0; i < 7; ++i) c.put<double>(0.5 * i);
  for (int i = 0; i < 36; ++i) c.put<double>(i == 0 ? 0.01 : 0.0);
  for (int i = 0; i < 6; ++i) c.put<double>(-1.0 - i);
  for (int i = 0; i < 36; ++i) c.put<double>(0.0);
  OdometryMsg m;
  decodeCdr(c.bytes().data(), c.bytes().size(), m);
  EXPECT_EQ(m.header.frame_id, "odom");
  EXPECT_EQ(m.child_frame_id, "base_link");
  EXPECT_EQ(m.position[0], 0.0);
  EXPECT_EQ(m.position[2], 1.0);
  EXPECT_EQ(m.orientation[3], 3.0);
  EXPECT_EQ(m.pose_covariance[0], 0.01);
  EXPECT_EQ(m.linear[0], -1.0);
  EXPECT_EQ(m.angular[2], -6.0);
}

TEST(CdrMessages, TfMessageWithTwoTransforms) {
  Cdr c;
  c.put<uint32_t>(2);
  for (int k = 0; k < 2; ++k) {
    c.header(1, 2, "base_link").str(k == 0 ? "laser" : "camera");
    for (double v : {0.25, -0.1, 0.3, 0.0, 0.0, std::sin(0.25), std::cos(0.25)}) c.put<double>(v);
  }
  TfMsg m;
  decodeCdr(c.bytes().data(), c.bytes().size(), m);
  ASSERT_EQ(m.transforms.size(), 2u);
  EXPECT_EQ(m.transforms[1].child_frame_id, "camera");
  EXPECT_EQ(m.transforms[0].header.frame_id, "base_link");
  EXPECT_EQ(m.transforms[0].translation[1], -0.1);
  EXPECT_EQ(m.transforms[0].rotation[3], std::cos(0.25));
}

TEST(CdrMessages, EveryPrefixOfAMessageIsAParseError) {
  const Cdr c = laserScan(true);
  const auto& b = c.bytes();
  for (size_t n = 0; n + 4 <= b.size(); ++n) {
    LaserScanMsg m;
    EXPECT_THROW(decodeCdr(b.data(), n, m), ParseError) << n << " of " << b.size() << " bytes";
  }
  // The same bytes as other types: errors, not crashes (they may happen to fit).
  for (size_t n = 0; n <= b.size(); ++n) {
    auto tryAll = [&](auto msg) {
      try {
        decodeCdr(b.data(), n, msg);
      } catch (const ParseError&) {
      }
    };
    tryAll(OdometryMsg{});
    tryAll(ImageMsg{});
    tryAll(CompressedImageMsg{});
    tryAll(CameraInfoMsg{});
    tryAll(TfMsg{});
  }
}

TEST(CdrMessages, AnUnknownEncapsulationIsNamed) {
  std::vector<uint8_t> b = laserScan(true).bytes();
  b[1] = 3;  // PL_CDR_LE: parameter lists, not what ROS 2 bags hold
  LaserScanMsg m;
  try {
    decodeCdr(b.data(), b.size(), m);
    FAIL() << "no error";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("encapsulation"), std::string::npos) << e.what();
  }
}

TEST(CdrMessages, AHugeSequenceCountIsAnErrorBeforeAnyAllocation) {
  Cdr c;
  c.header(1, 2, "f");
  for (int i = 0; i < 7; ++i) c.put<float>(0.f);
  c.put<uint32_t>(0xFFFFFFF0u);
  LaserScanMsg m;
  EXPECT_THROW(decodeCdr(c.bytes().data(), c.bytes().size(), m), ParseError);
}

}  // namespace
}  // namespace plugslam::io
