// Round trips through both archive back-ends.
#include "plugslam/archive.h"
#include "plugslam/sensor_data.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_map.h"
#include "plugslam/property_container.h"
#include "plugslam/value_types.h"
#include "round_trip.h"

namespace testplugin {

// A plugin-style value type: a struct with its own save/load, found by ADL.
struct Scan {
  std::vector<double> ranges;
  double angle_min = 0.0;
  double angle_increment = 0.0;
  std::string frame;
  std::int32_t seq = 0;
  std::map<std::string, std::vector<std::string>> tags;
  bool operator==(const Scan& o) const {
    return ranges == o.ranges && angle_min == o.angle_min && angle_increment == o.angle_increment &&
           frame == o.frame && seq == o.seq && tags == o.tags;
  }
};

// The fields, listed once for save (Ar = OutArchive, S = const Scan) and load, as the SDK's own
// types list theirs.
template <class Ar, class S>
void scanFields(Ar& ar, S& s) {
  ar.field("ranges", s.ranges)
      .field("angle_min", s.angle_min)
      .field("angle_increment", s.angle_increment)
      .field("frame", s.frame)
      .field("seq", s.seq)
      .field("tags", s.tags);
}

void save(plugslam::OutArchive& ar, const Scan& s) {
  ar.beginObject();
  scanFields(ar, s);
  ar.endObject();
}

void load(plugslam::InArchive& ar, Scan& s) {
  ar.beginObject();
  scanFields(ar, s);
  if (s.angle_increment < 0) ar.fail("angle_increment must be >= 0");
  ar.endObject();
}

}  // namespace testplugin

namespace plugslam {
namespace {

std::string write(ArchiveFormat f, const std::function<void(OutArchive&)>& fn) {
  std::ostringstream ss;
  auto ar = makeOutArchive(ss, f);
  fn(*ar);
  ar->finish();
  return ss.str();
}

template <class T>
std::string encode(ArchiveFormat f, const T& v) {
  return write(f, [&](OutArchive& ar) { save(ar, v); });
}

template <class T>
T decode(ArchiveFormat f, const std::string& bytes) {
  std::istringstream ss(bytes);
  auto ar = makeInArchive(ss, f, "test-input");
  T out{};
  load(*ar, out);
  return out;
}

using plugslam::testing::roundTrip;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

class ArchiveRoundTrip : public ::testing::TestWithParam<ArchiveFormat> {};

TEST_P(ArchiveRoundTrip, Scalars) {
  const ArchiveFormat f = GetParam();
  EXPECT_EQ(roundTrip(f, true), true);
  EXPECT_EQ(roundTrip(f, false), false);
  for (std::int32_t v : {0, 1, -1, std::numeric_limits<std::int32_t>::min(),
                         std::numeric_limits<std::int32_t>::max()}) {
    EXPECT_EQ(roundTrip(f, v), v);
  }
  for (std::int64_t v :
       {std::int64_t{0}, std::int64_t{-5}, std::numeric_limits<std::int64_t>::min(),
        std::numeric_limits<std::int64_t>::max()}) {
    EXPECT_EQ(roundTrip(f, v), v);
  }
  for (std::uint64_t v : {std::uint64_t{0}, std::uint64_t{127}, std::uint64_t{128},
                          std::numeric_limits<std::uint64_t>::max()}) {
    EXPECT_EQ(roundTrip(f, v), v);
  }
  EXPECT_EQ(roundTrip(f, std::uint32_t{4000000000u}), 4000000000u);
  for (double v :
       {0.0, -0.0, 0.1, 1.0 / 3.0, -2.5e-300, 1.7976931348623157e308,
        std::numeric_limits<double>::denorm_min(), M_PI, std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()}) {
    EXPECT_TRUE(sameBits(roundTrip(f, v), v)) << v;
  }
  EXPECT_TRUE(std::isnan(roundTrip(f, std::numeric_limits<double>::quiet_NaN())));
}

TEST_P(ArchiveRoundTrip, Strings) {
  const ArchiveFormat f = GetParam();
  for (const std::string s :
       {"", "plain", "~", "null", "true", "123", "1.5", "-", " lead and trail ", "a: b", "#hash",
        "multi\nline\n", "tab\there", "quote\"and'apostrophe", "ünïcödé ✓", "[flow]", "{x: 1}"}) {
    EXPECT_EQ(roundTrip(f, s), s);
  }
  if (f == ArchiveFormat::kBinary) {
    const std::string bytes("\0\xff\x01 binary", 10);
    EXPECT_EQ(roundTrip(f, bytes), bytes);
  } else {
    EXPECT_THROW(encode(f, std::string("\xff\xfe")), Error);  // text needs UTF-8
  }
}

TEST_P(ArchiveRoundTrip, StdContainers) {
  const ArchiveFormat f = GetParam();
  const std::vector<double> vd{1.0, -2.0, 1e-12};
  EXPECT_EQ(roundTrip(f, vd), vd);
  EXPECT_EQ(roundTrip(f, std::vector<double>{}), std::vector<double>{});
  const std::vector<std::string> vs{"a", "", "c"};
  EXPECT_EQ(roundTrip(f, vs), vs);
  const std::vector<std::vector<std::int64_t>> vv{{1, 2}, {}, {-3}};
  EXPECT_EQ(roundTrip(f, vv), vv);
  const std::map<std::string, double> md{{"b", 2.0}, {"a", 1.0}};
  EXPECT_EQ(roundTrip(f, md), md);
  const std::map<std::string, std::vector<std::string>> mv{{"k", {"x", "y"}}, {"e", {}}};
  EXPECT_EQ(roundTrip(f, mv), mv);
  EXPECT_EQ(roundTrip(f, std::map<std::string, int>{}), (std::map<std::string, int>{}));
  const std::vector<bool> vb{true, false, true};
  EXPECT_EQ(roundTrip(f, vb), vb);
}

TEST_P(ArchiveRoundTrip, EigenTypes) {
  const ArchiveFormat f = GetParam();
  const Eigen::Vector2d v2(1.5, -2.25);
  EXPECT_EQ(roundTrip(f, v2), v2);
  const Eigen::Vector3d v3 = Eigen::Vector3d::Random();
  EXPECT_EQ(roundTrip(f, v3), v3);
  const Eigen::Matrix3d m3 = Eigen::Matrix3d::Random();
  EXPECT_EQ(roundTrip(f, m3), m3);
  const Eigen::Matrix<double, 6, 6> m6 = Eigen::Matrix<double, 6, 6>::Random();
  EXPECT_EQ(roundTrip(f, m6), m6);
  const Eigen::VectorXd vx = Eigen::VectorXd::Random(7);
  EXPECT_EQ(roundTrip(f, vx), vx);
  EXPECT_EQ(roundTrip(f, Eigen::VectorXd()).size(), 0);
  const Eigen::MatrixXd mx = Eigen::MatrixXd::Random(3, 5);
  const Eigen::MatrixXd mx2 = roundTrip(f, mx);
  ASSERT_EQ(mx2.rows(), 3);
  ASSERT_EQ(mx2.cols(), 5);
  EXPECT_EQ(mx2, mx);
  const Eigen::MatrixXd empty(0, 4);
  EXPECT_EQ(roundTrip(f, empty).cols(), 4);
  const Eigen::Matrix<double, 2, 3, Eigen::RowMajor> rm = Eigen::Matrix<double, 2, 3>::Random();
  EXPECT_EQ(roundTrip(f, rm), rm);
  const Eigen::Matrix<double, 3, Eigen::Dynamic> m3x = Eigen::Matrix<double, 3, 4>::Random();
  EXPECT_EQ(roundTrip(f, m3x), m3x);
  const Eigen::RowVectorXd rv = Eigen::RowVectorXd::Random(4);
  EXPECT_EQ(roundTrip(f, rv), rv);

  Eigen::Isometry2d i2 = Eigen::Isometry2d::Identity();
  i2.rotate(0.3).pretranslate(Eigen::Vector2d(1.0, -4.0));
  EXPECT_EQ(roundTrip(f, i2).matrix(), i2.matrix());
  Eigen::Isometry3d i3 = Eigen::Isometry3d::Identity();
  i3.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()))
      .pretranslate(Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(roundTrip(f, i3).matrix(), i3.matrix());

  std::vector<Eigen::Vector2d> p2{{1, 2}, {3, 4}, {5, 6}};
  EXPECT_EQ(roundTrip(f, p2), p2);
  std::vector<Eigen::Vector3d> p3{{1, 2, 3}, {4, 5, 6}};
  EXPECT_EQ(roundTrip(f, p3), p3);
  EXPECT_TRUE(roundTrip(f, std::vector<Eigen::Vector3d>{}).empty());
  // Points of other sizes go through the generic vector path.
  std::vector<Eigen::Vector4d> p4{Eigen::Vector4d::Random(), Eigen::Vector4d::Random()};
  EXPECT_EQ(roundTrip(f, p4), p4);
}

TEST_P(ArchiveRoundTrip, WrongMatrixShapeIsAParseError) {
  const ArchiveFormat f = GetParam();
  const std::string bytes = encode(f, Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(decode<Eigen::Vector2d>(f, bytes), ParseError);
  EXPECT_THROW(decode<Eigen::Isometry2d>(f, bytes), ParseError);
  EXPECT_THROW(decode<std::vector<Eigen::Vector2d>>(f, bytes), ParseError);
  EXPECT_EQ(decode<Eigen::VectorXd>(f, bytes), Eigen::Vector3d(1, 2, 3));
  const std::string m = encode(f, Eigen::MatrixXd(Eigen::MatrixXd::Zero(2, 3)));
  EXPECT_THROW((decode<Eigen::Matrix<double, 3, Eigen::Dynamic>>(f, m)), ParseError);
  EXPECT_THROW(decode<std::int32_t>(f, encode(f, std::int64_t{1} << 40)), ParseError);
}

// One container holding every built-in value type, nested containers and a plugin type.
PropertyContainer everyBuiltIn() {
  PropertyContainer c;
  c.set<bool>("bool", true);
  c.set<std::int32_t>("int32", -42);
  c.set<std::int64_t>("int64", std::int64_t{1} << 50);
  c.set<std::uint64_t>("uint64", std::numeric_limits<std::uint64_t>::max());
  c.set<double>("double", 0.1);
  c.set<std::string>("string", "hello: world");
  c.set<std::vector<double>>("vector<double>", {1.0, 2.0, 3.5});
  c.set<std::vector<std::int64_t>>("vector<int64>", {-1, 0, 1});
  c.set<std::vector<std::string>>("vector<string>", {"a", "b"});
  c.set<std::map<std::string, double>>("map<string,double>", {{"x", 1.0}, {"y", 2.0}});
  c.set<std::map<std::string, std::string>>("map<string,string>", {{"k", "v"}});
  c.set<Eigen::Vector2d>("vector2d", Eigen::Vector2d::Random());
  c.set<Eigen::Vector3d>("vector3d", Eigen::Vector3d::Random());
  c.set<Eigen::Vector4d>("vector4d", Eigen::Vector4d::Random());
  c.set<Eigen::Matrix2d>("matrix2d", Eigen::Matrix2d::Random());
  c.set<Eigen::Matrix3d>("matrix3d", Eigen::Matrix3d::Random());
  c.set<Eigen::Matrix4d>("matrix4d", Eigen::Matrix4d::Random());
  c.set<Eigen::Matrix<double, 6, 6>>("matrix6d", Eigen::Matrix<double, 6, 6>::Random());
  c.set<Eigen::VectorXd>("vectorxd", Eigen::VectorXd::Random(5));
  c.set<Eigen::MatrixXd>("matrixxd", Eigen::MatrixXd::Random(4, 2));
  Eigen::Isometry2d i2 = Eigen::Isometry2d::Identity();
  i2.rotate(1.2).pretranslate(Eigen::Vector2d(3, 4));
  c.set<Eigen::Isometry2d>("isometry2d", i2);
  Eigen::Isometry3d i3 = Eigen::Isometry3d::Identity();
  i3.rotate(Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitZ()))
      .pretranslate(Eigen::Vector3d(1, 2, 3));
  c.set<Eigen::Isometry3d>("isometry3d", i3);
  c.set<std::vector<Eigen::Vector2d>>("points2d", {{0.5, 1.5}, {2.5, 3.5}});
  c.set<std::vector<Eigen::Vector3d>>("points3d", {{0.5, 1.5, 2.5}});
  PropertyContainer inner;
  inner.set<double>("deep", -1.0);
  inner.emplace<PropertyContainer>("deeper").set<std::string>("s", "x");
  c.set<PropertyContainer>("container", inner);
  c.emplace<PropertyContainer>("empty container");
  LaserScan scan;
  scan.stamp = 12.5;
  scan.angle_min = -1.5;
  scan.angle_increment = 0.01;
  scan.range_min = 0.1;
  scan.range_max = 30;
  scan.ranges = {1.0, 2.5, std::numeric_limits<double>::infinity(), 0.0};
  scan.mount = i2;
  c.set<LaserScan>("LaserScan", scan);
  c.set<Odometry2D>("Odometry2D", Odometry2D{3.25, i2});
  Image image;
  image.stamp = 4.5;
  image.resize(5, 3, 3);  // 45 bytes: exercises every base64 padding case with the others
  for (size_t k = 0; k < image.data.size(); ++k) image.data[k] = static_cast<uint8_t>(k * 37 + 1);
  c.set<Image>("Image", image);
  Image grey;
  grey.resize(4, 1, 1);
  grey.data = {0, 255, 128, 7};
  c.set<Image>("Image grey", grey);
  DepthImage depth;
  depth.stamp = 4.5;
  depth.resize(3, 2);
  depth.data = {0.0f, 1.25f, 3.1f, std::numeric_limits<float>::quiet_NaN(), 12.0f, 0.5f};
  c.set<DepthImage>("DepthImage", depth);
  CameraInfo camera;
  camera.setIntrinsics({{718.856, 718.856, 607.1928, 185.2157, 1241, 376}, Distortion{}});
  camera.baseline = 0.54;
  camera.mount = i3;
  c.set<CameraInfo>("CameraInfo", camera);
  FeatureSet features;
  features.camera = {700, 700, 600, 180, 0.54};
  features.width = 1241;
  features.height = 376;
  features.mount = i3;
  features.stamp = 4.5;
  uint8_t descriptor[32];
  for (int k = 0; k < 32; ++k) descriptor[k] = static_cast<uint8_t>(k * 7 + 3);
  features.pushStereo({100.5, 50.25}, 1.0, 12.5, 0.5, descriptor, 0x102030);
  features.pushStereo({10, 20}, 2.0, 0.0, 0.5, descriptor, 0xffffff);  // no depth
  c.set<FeatureSet>("FeatureSet", features);
  LandmarkMap landmarks;
  landmarks.push({1, 2, 3}, Eigen::Matrix3d::Identity() * 0.01, 7, descriptor, 0x405060, 11);
  landmarks.observations[0] = 3;
  landmarks.visible[0] = 5;
  c.set<LandmarkMap>("LandmarkMap", landmarks);
  // A raw rig (EuRoC-like): distortion on both cameras, the second one rotated and offset.
  CameraInfo rig = camera;
  rig.baseline = 0;
  rig.distortion = {Distortion::Model::kRadialTangential, {-0.2834, 0.0740, 1.9e-4, 1.8e-5}};
  rig.second = CameraIntrinsics{457.587, 456.134, 379.999, 255.238, 752, 480,
                                {Distortion::Model::kEquidistant, {0.1, -0.02, 3e-3, -4e-4}}};
  rig.second_pose = i3.inverse();
  c.set<CameraInfo>("CameraInfo rig", rig);
  return c;
}

void expectEqualContainers(const PropertyContainer& a, const PropertyContainer& b);

void expectEqualIntrinsics(const CameraIntrinsics& x, const CameraIntrinsics& y) {
  EXPECT_EQ(x.fx, y.fx);
  EXPECT_EQ(x.fy, y.fy);
  EXPECT_EQ(x.cx, y.cx);
  EXPECT_EQ(x.cy, y.cy);
  EXPECT_EQ(x.width, y.width);
  EXPECT_EQ(x.height, y.height);
  EXPECT_EQ(x.distortion.model, y.distortion.model);
  EXPECT_EQ(x.distortion.coefficients, y.distortion.coefficients);
}

// Expects each of the `members` equal in x and y, naming the entry `n` when one is not.
template <class T, class... M>
void expectEqualMembers(const T& x, const T& y, const std::string& n, M T::*... members) {
  const auto one = [&](auto member) { EXPECT_EQ(x.*member, y.*member) << n; };
  (one(members), ...);
}

template <class T>
bool equalAs(const PropertyContainer& a, const PropertyContainer& b, const std::string& n) {
  if (!a.holds<T>(n)) return false;
  if constexpr (std::is_same_v<T, PropertyContainer>) {
    expectEqualContainers(a.get<T>(n), b.get<T>(n));
  } else if constexpr (std::is_same_v<T, Eigen::Isometry2d> ||
                       std::is_same_v<T, Eigen::Isometry3d>) {
    EXPECT_EQ(a.get<T>(n).matrix(), b.get<T>(n).matrix()) << n;
  } else if constexpr (std::is_same_v<T, Eigen::MatrixXd> || std::is_same_v<T, Eigen::VectorXd>) {
    EXPECT_EQ(a.get<T>(n).rows(), b.get<T>(n).rows()) << n;
    EXPECT_EQ(a.get<T>(n).cols(), b.get<T>(n).cols()) << n;
    EXPECT_TRUE(a.get<T>(n) == b.get<T>(n)) << n;
  } else if constexpr (std::is_same_v<T, LaserScan>) {
    const auto &x = a.get<T>(n), &y = b.get<T>(n);
    expectEqualMembers(x, y, n, &T::stamp, &T::angle_min, &T::angle_increment, &T::range_min,
                       &T::range_max, &T::ranges);
    EXPECT_EQ(x.mount.matrix(), y.mount.matrix());
  } else if constexpr (std::is_same_v<T, Image>) {
    expectEqualMembers(a.get<T>(n), b.get<T>(n), n, &T::stamp, &T::width, &T::height, &T::channels,
                       &T::stride, &T::data);
  } else if constexpr (std::is_same_v<T, DepthImage>) {
    const auto &x = a.get<T>(n), &y = b.get<T>(n);
    expectEqualMembers(x, y, n, &T::stamp, &T::width, &T::height);
    EXPECT_EQ(x.data.size(), y.data.size());
    // Bit-exact, NaN included.
    if (x.data.size() == y.data.size()) {
      EXPECT_EQ(0, std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)));
    }
  } else if constexpr (std::is_same_v<T, CameraInfo>) {
    const auto &x = a.get<T>(n), &y = b.get<T>(n);
    expectEqualIntrinsics(x.intrinsics(), y.intrinsics());
    EXPECT_EQ(x.baseline, y.baseline);
    EXPECT_EQ(x.mount.matrix(), y.mount.matrix());
    EXPECT_EQ(x.second.has_value(), y.second.has_value()) << n;
    if (x.second && y.second) {
      expectEqualIntrinsics(*x.second, *y.second);
      EXPECT_EQ(x.second_pose.matrix(), y.second_pose.matrix());
    }
  } else if constexpr (std::is_same_v<T, FeatureSet>) {
    const auto &x = a.get<T>(n), &y = b.get<T>(n);
    expectEqualMembers(x.camera, y.camera, n, &PinholeCamera::fx, &PinholeCamera::cy,
                       &PinholeCamera::baseline);
    EXPECT_EQ(x.mount.matrix(), y.mount.matrix());
    expectEqualMembers(x, y, n, &T::width, &T::height, &T::stamp, &T::pixels, &T::pixel_sigma,
                       &T::inverse_depth, &T::inverse_depth_sigma, &T::points, &T::covariances,
                       &T::descriptor_bytes, &T::descriptors, &T::colours);
  } else if constexpr (std::is_same_v<T, LandmarkMap>) {
    expectEqualMembers(a.get<T>(n), b.get<T>(n), n, &T::positions, &T::covariances, &T::ids,
                       &T::observations, &T::visible, &T::last_seen, &T::colours,
                       &T::descriptor_bytes, &T::descriptors);
  } else if constexpr (std::is_same_v<T, Odometry2D>) {
    EXPECT_EQ(a.get<T>(n).stamp, b.get<T>(n).stamp);
    EXPECT_EQ(a.get<T>(n).pose.matrix(), b.get<T>(n).pose.matrix());
  } else {
    EXPECT_TRUE(a.get<T>(n) == b.get<T>(n)) << n;
  }
  return true;
}

void expectEqualContainers(const PropertyContainer& a, const PropertyContainer& b) {
  ASSERT_EQ(a.names(), b.names());
  for (const auto& n : a.names()) {
    ASSERT_EQ(a.at(n).type(), b.at(n).type()) << n;
    const bool checked =
        equalAs<bool>(a, b, n) || equalAs<std::int32_t>(a, b, n) ||
        equalAs<std::int64_t>(a, b, n) || equalAs<std::uint64_t>(a, b, n) ||
        equalAs<double>(a, b, n) || equalAs<std::string>(a, b, n) ||
        equalAs<std::vector<double>>(a, b, n) || equalAs<std::vector<std::int64_t>>(a, b, n) ||
        equalAs<std::vector<std::string>>(a, b, n) ||
        equalAs<std::map<std::string, double>>(a, b, n) ||
        equalAs<std::map<std::string, std::string>>(a, b, n) || equalAs<Eigen::Vector2d>(a, b, n) ||
        equalAs<Eigen::Vector3d>(a, b, n) || equalAs<Eigen::Vector4d>(a, b, n) ||
        equalAs<Eigen::Matrix2d>(a, b, n) || equalAs<Eigen::Matrix3d>(a, b, n) ||
        equalAs<Eigen::Matrix4d>(a, b, n) || equalAs<Eigen::Matrix<double, 6, 6>>(a, b, n) ||
        equalAs<Eigen::VectorXd>(a, b, n) || equalAs<Eigen::MatrixXd>(a, b, n) ||
        equalAs<Eigen::Isometry2d>(a, b, n) || equalAs<Eigen::Isometry3d>(a, b, n) ||
        equalAs<std::vector<Eigen::Vector2d>>(a, b, n) ||
        equalAs<std::vector<Eigen::Vector3d>>(a, b, n) || equalAs<PropertyContainer>(a, b, n) ||
        equalAs<testplugin::Scan>(a, b, n) || equalAs<LaserScan>(a, b, n) ||
        equalAs<Odometry2D>(a, b, n) || equalAs<Image>(a, b, n) ||
        equalAs<DepthImage>(a, b, n) || equalAs<CameraInfo>(a, b, n) ||
        equalAs<FeatureSet>(a, b, n) || equalAs<LandmarkMap>(a, b, n);
    EXPECT_TRUE(checked) << "no comparison for property '" << n << "' of type "
                         << a.at(n).typeName();
  }
}

TEST_P(ArchiveRoundTrip, ContainerWithEveryBuiltInType) {
  const ArchiveFormat f = GetParam();
  const PropertyContainer c = everyBuiltIn();
  // Every built-in tag is exercised: the container covers the whole SDK registry.
  std::vector<std::string> tags;
  for (const auto& p : c) tags.push_back(p.tag());
  for (const auto& t : ValueTypes::instance().tags()) {
    auto info = ValueTypes::instance().findByTag(t);
    if (info->owner != "sdk") continue;
    EXPECT_NE(std::find(tags.begin(), tags.end(), t), tags.end()) << "built-in not tested: " << t;
  }
  const PropertyContainer back = roundTrip(f, c);
  expectEqualContainers(c, back);
}

TEST_P(ArchiveRoundTrip, LoadReplacesTheContainerContents) {
  const ArchiveFormat f = GetParam();
  PropertyContainer src;
  src.set<double>("a", 1.0);
  PropertyContainer dst;
  dst.set<int>("stale", 1);
  std::istringstream in(encode(f, src));
  auto ar = makeInArchive(in, f);
  load(*ar, dst);
  EXPECT_EQ(dst.names(), std::vector<std::string>{"a"});
}

class UserTypeTest : public ::testing::TestWithParam<ArchiveFormat> {
 protected:
  void SetUp() override {
    ValueTypes::instance().add<testplugin::Scan>("testplugin.Scan", "testplugin");
  }
  void TearDown() override { ValueTypes::instance().removeOwner("testplugin"); }
};

testplugin::Scan sampleScan() {
  testplugin::Scan s;
  s.ranges = {1.0, 2.0, std::numeric_limits<double>::infinity(), 0.25};
  s.angle_min = -M_PI / 2;
  s.angle_increment = M_PI / 180;
  s.frame = "front_laser";
  s.seq = 17;
  s.tags = {{"quality", {"good"}}, {"none", {}}};
  return s;
}

TEST_P(UserTypeTest, RoundTripsInsideAContainer) {
  const ArchiveFormat f = GetParam();
  PropertyContainer c;
  c.set<double>("stamp", 12.5);
  c.set<testplugin::Scan>("scan", sampleScan());
  c.emplace<PropertyContainer>("nested").set<testplugin::Scan>("scan2", sampleScan());
  EXPECT_EQ(c.at("scan").tag(), "testplugin.Scan");
  const PropertyContainer back = roundTrip(f, c);
  expectEqualContainers(c, back);
  EXPECT_EQ(back.get<testplugin::Scan>("scan"), sampleScan());

  try {
    back.get<double>("scan");
    FAIL();
  } catch (const PropertyTypeMismatch& e) {
    EXPECT_NE(std::string(e.what()).find("testplugin.Scan"), std::string::npos) << e.what();
  }
}

TEST_P(UserTypeTest, UnknownTagAfterThePluginIsGone) {
  const ArchiveFormat f = GetParam();
  PropertyContainer c;
  c.set<testplugin::Scan>("scan", sampleScan());
  const std::string bytes = encode(f, c);
  EXPECT_EQ(ValueTypes::instance().removeOwner("testplugin"), 1u);
  try {
    decode<PropertyContainer>(f, bytes);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("'testplugin.Scan'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("plugin 'testplugin'"), std::string::npos) << msg;
    EXPECT_EQ(e.file(), "test-input");
  }
}

TEST_P(UserTypeTest, SavingAnUnregisteredTypeIsRefused) {
  const ArchiveFormat f = GetParam();
  struct Local {
    int x = 0;
  };
  PropertyContainer c;
  c.set<Local>("local", Local{});
  EXPECT_THROW(encode(f, c), Error);
  ValueTypes::instance().removeOwner("testplugin");
  c.clear();
  c.set<testplugin::Scan>("scan", sampleScan());
  try {
    encode(f, c);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'scan'"), std::string::npos) << e.what();
  }
}

TEST_P(UserTypeTest, UserLoadCanRejectValues) {
  const ArchiveFormat f = GetParam();
  testplugin::Scan s = sampleScan();
  s.angle_increment = -1.0;
  try {
    decode<testplugin::Scan>(f, encode(f, s));
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("angle_increment must be >= 0"), std::string::npos)
        << e.what();
  }
}

std::string formatParamName(const ::testing::TestParamInfo<ArchiveFormat>& info) {
  return formatName(info.param);
}

}  // namespace

// What GoogleTest prints as GetParam() (gtest_discover_tests puts it in the ctest name): the
// format's name, not the enum's bytes. In plugslam, where argument-dependent lookup finds it.
void PrintTo(ArchiveFormat f, std::ostream* os) { *os << formatName(f); }

namespace {

INSTANTIATE_TEST_SUITE_P(Formats, ArchiveRoundTrip,
                         ::testing::Values(ArchiveFormat::kBinary, ArchiveFormat::kText),
                         formatParamName);
INSTANTIATE_TEST_SUITE_P(Formats, UserTypeTest,
                         ::testing::Values(ArchiveFormat::kBinary, ArchiveFormat::kText),
                         formatParamName);

TEST(TextArchive, FieldsAreFoundByNameInAnyOrder) {
  const std::string yaml = R"(plugslam_archive: 1
data:
  pose:
    value: [1, 0, 0, 1, 5, 6]
    type: isometry2d
  count: {value: 3, type: int32}
)";
  const PropertyContainer c = decode<PropertyContainer>(ArchiveFormat::kText, yaml);
  EXPECT_EQ(c.names(), (std::vector<std::string>{"pose", "count"}));
  EXPECT_EQ(c.get<Eigen::Isometry2d>("pose").translation(), Eigen::Vector2d(5, 6));
  EXPECT_EQ(c.get<std::int32_t>("count"), 3);
}

TEST(TextArchive, JsonInputIsAccepted) {
  const std::string json =
      R"({"plugslam_archive": 1, "data": {"x": {"type": "double", "value": 2.5}}})";
  EXPECT_DOUBLE_EQ(decode<PropertyContainer>(ArchiveFormat::kText, json).get<double>("x"), 2.5);
}

ParseError parseErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ParseError& e) {
    return e;
  }
  ADD_FAILURE() << "expected a ParseError";
  return ParseError("", 0, "");
}

TEST(TextArchive, MissingFieldIsNamed) {
  const std::string yaml = R"(plugslam_archive: 1
data:
  scan:
    type: double
)";
  const ParseError e = parseErrorOf([&] { decode<PropertyContainer>(ArchiveFormat::kText, yaml); });
  const std::string msg = e.what();
  EXPECT_NE(msg.find("missing field 'value'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'scan'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fields present: type"), std::string::npos) << msg;
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.file(), "test-input");
}

// A CameraInfo archived before ABI 1.5 (no distortion, no second camera) still loads, as an
// undistorted camera without a second one; both back-ends find fields by name.
TEST_P(ArchiveRoundTrip, CameraInfoFromBeforeDistortionLoads) {
  const std::string bytes = write(GetParam(), [](OutArchive& ar) {
    ar.beginObject();
    ar.field("fx", 718.856).field("fy", 718.856).field("cx", 607.19).field("cy", 185.22);
    ar.field("width", std::int32_t{1241}).field("height", std::int32_t{376});
    ar.field("baseline", 0.54).field("mount", Eigen::Isometry3d::Identity());
    ar.endObject();
  });
  const CameraInfo c = decode<CameraInfo>(GetParam(), bytes);
  EXPECT_EQ(c.fx, 718.856);
  EXPECT_EQ(c.width, 1241);
  EXPECT_EQ(c.baseline, 0.54);
  EXPECT_EQ(c.distortion.model, Distortion::Model::kNone);
  EXPECT_TRUE(c.distortion.coefficients.empty());
  EXPECT_FALSE(c.second.has_value());
}

TEST_P(ArchiveRoundTrip, DistortionThatDoesNotFitItsModelIsAParseError) {
  Distortion d{Distortion::Model::kEquidistant, {0.1, 0.2, 0.3}};
  const std::string bad = encode(GetParam(), d);
  const ParseError e = parseErrorOf([&] { decode<Distortion>(GetParam(), bad); });
  EXPECT_NE(std::string(e.what()).find("3 coefficients do not fit the equidistant model"),
            std::string::npos)
      << e.what();
  const std::string unknown = write(GetParam(), [](OutArchive& ar) {
    ar.beginObject();
    ar.field("model", std::string("kannala")).field("coefficients", std::vector<double>{});
    ar.endObject();
  });
  const ParseError u = parseErrorOf([&] { decode<Distortion>(GetParam(), unknown); });
  EXPECT_NE(std::string(u.what()).find("unknown distortion model 'kannala'"), std::string::npos)
      << u.what();
}

TEST(Distortion, ModelNamesOfDatasetsAndRos) {
  Distortion::Model m = Distortion::Model::kEquidistant;
  for (const char* n : {"radial-tangential", "radtan", "plumb_bob", "rational_polynomial",
                        "Plumb_Bob"}) {
    ASSERT_TRUE(parseDistortionModel(n, m)) << n;
    EXPECT_EQ(m, Distortion::Model::kRadialTangential) << n;
  }
  for (const char* n : {"equidistant", "fisheye"}) {
    ASSERT_TRUE(parseDistortionModel(n, m)) << n;
    EXPECT_EQ(m, Distortion::Model::kEquidistant) << n;
  }
  for (const char* n : {"", "none"}) {
    ASSERT_TRUE(parseDistortionModel(n, m)) << n;
    EXPECT_EQ(m, Distortion::Model::kNone) << n;
  }
  EXPECT_FALSE(parseDistortionModel("double_sphere", m));
  for (auto model : {Distortion::Model::kNone, Distortion::Model::kRadialTangential,
                     Distortion::Model::kEquidistant}) {
    ASSERT_TRUE(parseDistortionModel(distortionModelName(model), m));
    EXPECT_EQ(m, model);
  }
}

TEST(Distortion, CountsAndIdentity) {
  using M = Distortion::Model;
  EXPECT_TRUE((Distortion{M::kNone, {}}).valid());
  EXPECT_FALSE((Distortion{M::kNone, {0.1}}).valid());
  for (size_t n : {4, 5, 8, 12, 14}) {
    EXPECT_TRUE((Distortion{M::kRadialTangential, std::vector<double>(n, 0.0)}).valid()) << n;
  }
  for (size_t n : {0, 3, 6, 7, 9, 13, 15}) {
    EXPECT_FALSE((Distortion{M::kRadialTangential, std::vector<double>(n, 0.0)}).valid()) << n;
  }
  EXPECT_TRUE((Distortion{M::kEquidistant, {0, 0, 0, 0}}).valid());
  EXPECT_FALSE((Distortion{M::kEquidistant, {0, 0, 0, 0, 0}}).valid());
  EXPECT_TRUE((Distortion{M::kRadialTangential, {0, 0, 0, 0}}).isIdentity());
  EXPECT_FALSE((Distortion{M::kRadialTangential, {0, 0, 1e-9, 0}}).isIdentity());
  EXPECT_TRUE((Distortion{}).isIdentity());
}

TEST(CameraInfo, IntrinsicsOfTheFirstCameraRoundTrip) {
  CameraInfo c;
  const CameraIntrinsics k{458.654, 457.296, 367.215, 248.375, 752, 480,
                           {Distortion::Model::kRadialTangential, {-0.28, 0.07, 2e-4, 2e-5}}};
  c.setIntrinsics(k);
  EXPECT_EQ(c.fx, 458.654);
  EXPECT_EQ(c.cy, 248.375);
  EXPECT_EQ(c.height, 480);
  const CameraIntrinsics back = c.intrinsics();
  EXPECT_EQ(back.fy, k.fy);
  EXPECT_EQ(back.cx, k.cx);
  EXPECT_EQ(back.width, k.width);
  EXPECT_EQ(back.distortion.coefficients, k.distortion.coefficients);
}

TEST(TextArchive, MalformedInputRaisesParseErrorWithLine) {
  const std::string bad_yaml = "plugslam_archive: 1\ndata: [1, 2\n";
  EXPECT_GT(parseErrorOf([&] { decode<double>(ArchiveFormat::kText, bad_yaml); }).line(), 0);

  const ParseError wrong_type = parseErrorOf([&] {
    decode<PropertyContainer>(ArchiveFormat::kText,
                              "plugslam_archive: 1\ndata:\n  x:\n    type: double\n"
                              "    value: abc\n");
  });
  EXPECT_EQ(wrong_type.line(), 5);
  EXPECT_NE(std::string(wrong_type.what()).find("'x.value'"), std::string::npos)
      << wrong_type.what();
  EXPECT_NE(std::string(wrong_type.what()).find("expected a number, found 'abc'"),
            std::string::npos)
      << wrong_type.what();

  const ParseError bad_point = parseErrorOf([&] {
    decode<std::vector<Eigen::Vector2d>>(ArchiveFormat::kText,
                                         "plugslam_archive: 1\ndata: [1, 2, x]\n");
  });
  EXPECT_NE(std::string(bad_point.what()).find("'x'"), std::string::npos) << bad_point.what();

  EXPECT_THROW(decode<double>(ArchiveFormat::kText, ""), ParseError);
  EXPECT_THROW(decode<double>(ArchiveFormat::kText, "- just\n- a list\n"), ParseError);
  EXPECT_THROW(decode<double>(ArchiveFormat::kText, "data: 1\n"), ParseError);
  EXPECT_THROW(decode<double>(ArchiveFormat::kText, "plugslam_archive: 2\ndata: 1\n"), ParseError);
  EXPECT_THROW(decode<double>(ArchiveFormat::kText, "plugslam_archive: 1\n"), ParseError);
  EXPECT_THROW(decode<std::int64_t>(ArchiveFormat::kText, "plugslam_archive: 1\ndata: 1.5\n"),
               ParseError);
  EXPECT_THROW(decode<std::int64_t>(ArchiveFormat::kText,
                                    "plugslam_archive: 1\ndata: 99999999999999999999\n"),
               ParseError);
  EXPECT_THROW(decode<std::uint64_t>(ArchiveFormat::kText, "plugslam_archive: 1\ndata: -1\n"),
               ParseError);
  EXPECT_THROW(decode<bool>(ArchiveFormat::kText, "plugslam_archive: 1\ndata: maybe\n"),
               ParseError);
  EXPECT_THROW(decode<std::string>(ArchiveFormat::kText, "plugslam_archive: 1\ndata: [a]\n"),
               ParseError);
  EXPECT_THROW(
      decode<std::vector<double>>(ArchiveFormat::kText, "plugslam_archive: 1\ndata: {a: 1}\n"),
      ParseError);
  EXPECT_THROW(
      decode<PropertyContainer>(ArchiveFormat::kText, "plugslam_archive: 1\ndata: {a: 1, a: 2}\n"),
      ParseError);
  EXPECT_THROW(decode<PropertyContainer>(ArchiveFormat::kText,
                                         "plugslam_archive: 1\ndata: {a: {type: nosuch, value: "
                                         "1}}\n"),
               ParseError);
}

TEST(Archive, WriterMisuseIsALogicError) {
  for (ArchiveFormat f : {ArchiveFormat::kBinary, ArchiveFormat::kText}) {
    std::ostringstream ss;
    auto ar = makeOutArchive(ss, f);
    ar->beginObject();
    EXPECT_THROW(ar->writeDouble(1.0), std::logic_error);  // no key
    ar->key("a");
    EXPECT_THROW(ar->key("b"), std::logic_error);  // two keys
    ar->writeDouble(1.0);
    EXPECT_THROW(ar->key("a"), std::logic_error);  // duplicate
    EXPECT_THROW(ar->finish(), std::logic_error);  // unclosed
    ar->key("arr");
    ar->beginArray(2);
    ar->writeInt(1);
    EXPECT_THROW(ar->endArray(), std::logic_error);  // short array
  }
}

TEST(Archive, FieldsSkippedByTheReaderDoNotDisturbTheRest) {
  for (ArchiveFormat f : {ArchiveFormat::kBinary, ArchiveFormat::kText}) {
    const std::string bytes = write(f, [](OutArchive& ar) {
      ar.beginArray(3);
      ar.beginObject();
      ar.field("skip", std::vector<std::string>{"x", "y"}).field("keep", 1.5);
      ar.endObject();
      ar.beginArray(2);
      ar.writeInt(7);
      ar.writeInt(8);
      ar.endArray();
      ar.writeString("last");
      ar.endArray();
    });
    std::istringstream in(bytes);
    auto ar = makeInArchive(in, f);
    ASSERT_EQ(ar->beginArray(), 3u);
    ar->beginObject();
    EXPECT_TRUE(ar->hasKey("skip"));
    EXPECT_FALSE(ar->hasKey("nope"));
    EXPECT_EQ(ar->keys(), (std::vector<std::string>{"skip", "keep"}));
    ar->key("keep");
    EXPECT_EQ(ar->readDouble(), 1.5);
    ar->endObject();
    EXPECT_EQ(ar->beginArray(), 2u);
    ar->endArray();  // both elements skipped
    EXPECT_EQ(ar->readString(), "last");
    EXPECT_THROW(ar->readString(), ParseError);  // past the end
    ar->endArray();
  }
}

TEST(BinaryArchive, SeveralArchivesFollowEachOtherInOneStream) {
  std::stringstream ss;
  for (int i = 0; i < 3; ++i) {
    auto ar = makeOutArchive(ss, ArchiveFormat::kBinary);
    save(*ar, std::vector<double>(static_cast<std::size_t>(i + 1), i * 1.5));
    ar->finish();
  }
  for (int i = 0; i < 3; ++i) {
    auto ar = makeInArchive(ss, ArchiveFormat::kBinary);
    std::vector<double> v;
    load(*ar, v);
    EXPECT_EQ(v, std::vector<double>(static_cast<std::size_t>(i + 1), i * 1.5));
  }
  EXPECT_THROW(makeInArchive(ss, ArchiveFormat::kBinary), ParseError);  // nothing left
}

// Size/speed sanity: 100k points in each of two clouds through the binary back-end. The archive
// is the raw doubles plus a small constant; the time is printed for the record, not asserted.
TEST(BinaryArchive, HundredThousandPointsRoundTrip) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  PropertyContainer c;
  auto& p2 = c.emplace<std::vector<Eigen::Vector2d>>("points2d");
  auto& p3 = c.emplace<std::vector<Eigen::Vector3d>>("points3d");
  for (int i = 0; i < 100000; ++i) {
    p2.emplace_back(u(rng), u(rng));
    p3.emplace_back(u(rng), u(rng), u(rng));
  }
  const auto t0 = std::chrono::steady_clock::now();
  const std::string bytes = encode(ArchiveFormat::kBinary, c);
  const auto t1 = std::chrono::steady_clock::now();
  const PropertyContainer back = decode<PropertyContainer>(ArchiveFormat::kBinary, bytes);
  const auto t2 = std::chrono::steady_clock::now();
  EXPECT_TRUE(back.get<std::vector<Eigen::Vector2d>>("points2d") == p2);
  EXPECT_TRUE(back.get<std::vector<Eigen::Vector3d>>("points3d") == p3);
  const std::size_t raw = 100000 * (2 + 3) * sizeof(double);
  EXPECT_GE(bytes.size(), raw);
  EXPECT_LT(bytes.size(), raw + 200) << "the blobs should carry almost no overhead";
  const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
  std::cout << "[ info ] 100k+100k points: " << bytes.size() << " bytes, save " << ms(t1 - t0)
            << " ms, load " << ms(t2 - t1) << " ms\n";
}

TEST(TextArchive, TenThousandPointsRoundTrip) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 10000; ++i) pts.emplace_back(u(rng), u(rng), u(rng));
  const auto t0 = std::chrono::steady_clock::now();
  const std::string text = encode(ArchiveFormat::kText, pts);
  const auto back = decode<std::vector<Eigen::Vector3d>>(ArchiveFormat::kText, text);
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_TRUE(back == pts);
  std::cout << "[ info ] 10k points as text: " << text.size() << " bytes, round trip "
            << std::chrono::duration<double, std::milli>(t1 - t0).count() << " ms\n";
}

}  // namespace
}  // namespace plugslam
