// sim2d world: ray casting against analytic geometry and brute force, loaders.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>

#include "plugslam/errors.h"
#include "sim2d/laser.h"
#include "sim2d/world.h"
#include "temp_dir.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

World squareRoom(double size) {
  const Eigen::Vector2d p0(0, 0), p1(size, 0), p2(size, size), p3(0, size);
  return World({{p0, p1}, {p1, p2}, {p2, p3}, {p3, p0}});
}

// Distance from o along unit d to the boundary of [0,size]^2 (o inside).
double analyticSquare(const Eigen::Vector2d& o, const Eigen::Vector2d& d, double size) {
  double t = kInf;
  if (d.x() > 0) t = std::min(t, (size - o.x()) / d.x());
  if (d.x() < 0) t = std::min(t, -o.x() / d.x());
  if (d.y() > 0) t = std::min(t, (size - o.y()) / d.y());
  if (d.y() < 0) t = std::min(t, -o.y() / d.y());
  return t;
}

// This test process's own folder (ctest runs each test in a process of its own).
const plugslam::testing::TempDir& scratch() {
  static const plugslam::testing::TempDir tmp;
  return tmp;
}

std::string writeTemp(const std::string& name, const std::string& content) {
  return scratch().write(name, content);
}

TEST(Sim2dWorld, ScanInSquareRoomMatchesAnalyticDistances) {
  const double size = 10.0;
  const World world = squareRoom(size);
  LaserConfig laser;
  laser.name = "test";
  laser.mount = Eigen::Vector3d(0.2, 0.1, 0.5);
  laser.fov = 2.0 * M_PI - 0.01;
  laser.beams = 721;
  laser.range_sigma = 0.0;
  laser.max_range = 100.0;
  const Eigen::Vector3d robot(3.0, 4.0, 0.3);
  LaserScan scan;
  simulateScan(world, robot, laser, nullptr, &scan);
  ASSERT_EQ(scan.ranges.size(), 721u);
  EXPECT_DOUBLE_EQ(scan.angle_min, -0.5 * laser.fov);
  EXPECT_DOUBLE_EQ(scan.angle_increment, laser.fov / 720.0);
  const Eigen::Vector2d origin(3.0 + 0.2 * std::cos(0.3) - 0.1 * std::sin(0.3),
                               4.0 + 0.2 * std::sin(0.3) + 0.1 * std::cos(0.3));
  for (int i = 0; i < laser.beams; ++i) {
    const double a = 0.3 + 0.5 + scan.angle_min + i * scan.angle_increment;
    const double expected = analyticSquare(origin, Eigen::Vector2d(std::cos(a), std::sin(a)), size);
    ASSERT_NEAR(scan.ranges[i], expected, 1e-9) << "beam " << i;
  }
}

TEST(Sim2dWorld, RangesBeyondMaxRangeAreNaN) {
  const World world = squareRoom(10.0);
  LaserConfig laser;
  laser.range_sigma = 0.0;
  laser.max_range = 3.0;
  laser.beams = 181;
  LaserScan scan;
  simulateScan(world, Eigen::Vector3d(5, 5, 0), laser, nullptr, &scan);
  int valid = 0;
  for (double r : scan.ranges) {
    if (std::isfinite(r)) {
      ++valid;
      EXPECT_LE(r, 3.0);
    }
  }
  EXPECT_EQ(valid, 0);  // every wall is 5 m or more away
  laser.max_range = 30.0;
  laser.dropout = 0.3;
  Rng rng(5);
  simulateScan(world, Eigen::Vector3d(5, 5, 0), laser, &rng, &scan);
  int dropped = 0;
  for (double r : scan.ranges) dropped += std::isnan(r) ? 1 : 0;
  EXPECT_GT(dropped, 181 * 0.15);
  EXPECT_LT(dropped, 181 * 0.45);
}

TEST(Sim2dWorld, GridCastEqualsBruteForce) {
  std::mt19937_64 engine(42);
  auto uniform = [&](double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(engine() >> 11) / 9007199254740992.0);
  };
  std::vector<Segment> segments;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d a(uniform(-25, 25), uniform(-25, 25));
    const double len = uniform(0.2, 6.0), ang = uniform(-M_PI, M_PI);
    segments.push_back({a, a + len * Eigen::Vector2d(std::cos(ang), std::sin(ang))});
  }
  // Long segments crossing many cells, axis-aligned and diagonal.
  segments.push_back({{-30, -30}, {30, 30}});
  segments.push_back({{-30, 10}, {30, 10}});
  segments.push_back({{7, -30}, {7, 30}});
  const World world(segments);
  for (int k = 0; k < 20000; ++k) {
    const Eigen::Vector2d o(uniform(-35, 35), uniform(-35, 35));
    const double ang = k % 10 == 0 ? (k / 10 % 4) * M_PI / 2 : uniform(-M_PI, M_PI);
    const Eigen::Vector2d d(std::cos(ang), std::sin(ang));
    const double max_range = uniform(1.0, 60.0);
    double brute = kInf;
    for (const Segment& s : segments) {
      const Eigen::Vector2d e = s.b - s.a, ao = s.a - o;
      const double den = d.x() * e.y() - d.y() * e.x();
      if (den == 0.0) continue;
      const double t = (ao.x() * e.y() - ao.y() * e.x()) / den;
      const double u = (ao.x() * d.y() - ao.y() * d.x()) / den;
      if (t >= 0.0 && u >= 0.0 && u <= 1.0) brute = std::min(brute, t);
    }
    if (brute > max_range) brute = kInf;
    ASSERT_EQ(world.castRay(o, d, max_range), brute) << "ray " << k;
  }
}

TEST(Sim2dWorld, CrossesAndClearance) {
  const World world = squareRoom(10.0);
  EXPECT_FALSE(world.crosses({1, 1}, {9, 9}));
  EXPECT_TRUE(world.crosses({5, 5}, {11, 5}));
  EXPECT_TRUE(world.crosses({-1, 5}, {1, 5}));
  EXPECT_NEAR(world.clearance({3, 4}, 100.0), 3.0, 1e-12);
  EXPECT_NEAR(world.clearance({5, 5}, 2.0), 2.0, 1e-12);  // capped
}

// The scan's cost is printed, not asserted: the machine is shared, and speed is a benchmark's
// business (scripts/bench/sim2d.sh).
TEST(Sim2dWorld, OfficeIsLargeAndItsScanCostIsPrinted) {
  const World office = World::office();
  EXPECT_GE(office.boundsMax().x() - office.boundsMin().x(), 60.0);
  EXPECT_GE(office.boundsMax().y() - office.boundsMin().y(), 40.0);
  EXPECT_GT(office.segments().size(), 150u);
  // Down the lower corridor's centre line: doors and alcoves are off the line, so the ray
  // reaches the far outer wall.
  EXPECT_NEAR(office.castRay({1.25, 13.25}, {1, 0}, 100.0), 62.75, 1e-9);

  LaserConfig laser;
  laser.beams = 1081;
  laser.range_sigma = 0.01;
  Rng rng(1);
  LaserScan scan;
  const int n = 400;
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d pose(1.25 + 0.15 * i, 13.25, 0.01 * i);
    simulateScan(office, pose, laser, &rng, &scan);
  }
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / n;
  std::cout << "1081-beam scan in the office: " << ms << " ms\n";
  RecordProperty("scan_ms", std::to_string(ms));
  EXPECT_EQ(scan.ranges.size(), 1081u);
}

TEST(Sim2dWorld, LoadsSegmentList) {
  const std::string path = writeTemp("good.segments",
                                     "# a room\n"
                                     "0 0 4 0\n"
                                     "\n"
                                     "4 0 4 3   # right wall\n"
                                     "  4 3 0 3\n"
                                     "0 3 0 0\n");
  const World world = World::loadSegments(path);
  ASSERT_EQ(world.segments().size(), 4u);
  EXPECT_EQ(world.segments()[1].a, Eigen::Vector2d(4, 0));
  EXPECT_EQ(world.segments()[1].b, Eigen::Vector2d(4, 3));
  EXPECT_NEAR(world.castRay({1, 1}, {1, 0}, 10.0), 3.0, 1e-12);

  // Round trip through saveSegments.
  const std::string copy = scratch().file("copy.segments");
  World::office().saveSegments(copy);
  EXPECT_EQ(World::loadSegments(copy).segments().size(), World::office().segments().size());
}

void expectParseError(const std::string& path, int line, const std::string& fragment) {
  try {
    World::loadSegments(path);
    FAIL() << "expected ParseError for " << path;
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Sim2dWorld, RejectsMalformedSegmentList) {
  expectParseError(writeTemp("few.segments", "0 0 1 1\n# c\n0 0 1\n"), 3, "expected four numbers");
  expectParseError(writeTemp("many.segments", "0 0 1 1 5\n"), 1, "got 5 fields");
  expectParseError(writeTemp("nan.segments", "0 0 1 1\n0 0 x 1\n"), 2, "field 3");
  expectParseError(writeTemp("garbage.segments", "0 0 1 1.5m\n"), 1, "'1.5m'");
  expectParseError(writeTemp("point.segments", "\n2 2 2 2\n"), 2, "distinct");
  expectParseError(writeTemp("empty.segments", "# nothing\n\n"), 2, "at least one segment");
  EXPECT_THROW(World::loadSegments(scratch().file("missing.segments")), InputError);
}

TEST(Sim2dWorld, LoadsAsciiPgm) {
  // 5 x 4 image, one occupied pixel at column 1, row 2 (rows counted from the top).
  const std::string path = writeTemp("one.pgm",
                                     "P2\n# a comment\n5 4\n255\n"
                                     "255 255 255 255 255\n"
                                     "255 255 255 255 255\n"
                                     "255 0 255 255 255\n"
                                     "255 255 255 255 255\n");
  const World world = World::loadPgm(path, 0.5, Eigen::Vector2d(-1.0, 2.0));
  ASSERT_EQ(world.segments().size(), 4u);
  // Pixel (1, 2) covers x in [-0.5, 0], y in [2.5, 3.0].
  EXPECT_NEAR(world.boundsMin().x(), -0.5, 1e-12);
  EXPECT_NEAR(world.boundsMax().x(), 0.0, 1e-12);
  EXPECT_NEAR(world.boundsMin().y(), 2.5, 1e-12);
  EXPECT_NEAR(world.boundsMax().y(), 3.0, 1e-12);
  EXPECT_NEAR(world.castRay({-3.0, 2.75}, {1, 0}, 10.0), 2.5, 1e-12);
}

TEST(Sim2dWorld, LoadsBinaryPgmAndMergesRuns) {
  // 6 x 3 image: a full row of occupied pixels in the middle -> one rectangle of 4 segments.
  std::string data = "P5 6 3 255\n";
  for (int i = 0; i < 6; ++i) data.push_back(static_cast<char>(254));
  for (int i = 0; i < 6; ++i) data.push_back(static_cast<char>(0));
  for (int i = 0; i < 6; ++i) data.push_back(static_cast<char>(205));  // unknown: free
  const World world = World::loadPgm(writeTemp("row.pgm", data), 0.1, Eigen::Vector2d(0, 0));
  ASSERT_EQ(world.segments().size(), 4u);
  EXPECT_NEAR(world.castRay({0.3, 0.0}, {0, 1}, 10.0), 0.1, 1e-12);
  EXPECT_NEAR(world.castRay({0.3, 0.3}, {0, -1}, 10.0), 0.1, 1e-12);
}

void expectPgmError(const std::string& name, const std::string& content, int line,
                    const std::string& fragment) {
  const std::string path = writeTemp(name, content);
  try {
    World::loadPgm(path, 0.1, Eigen::Vector2d(0, 0));
    FAIL() << "expected ParseError for " << name;
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Sim2dWorld, RejectsMalformedPgm) {
  expectPgmError("magic.pgm", "P3\n2 2\n255\n0 0 0 0\n", 1, "P2 or P5");
  expectPgmError("width.pgm", "P2\n# c\nx 2\n255\n", 3, "image width");
  expectPgmError("value.pgm", "P2\n2 2\n255\n0 0\n0 300\n", 5, "grey value");
  expectPgmError("short.pgm", "P2\n2 2\n255\n0 0\n0\n", 6, "unexpected end of file");
  expectPgmError("truncated.pgm", std::string("P5\n2 2\n255\n") + '\0', 4, "bytes of pixel data");
  EXPECT_THROW(World::loadPgm(writeTemp("free.pgm", "P2 1 1 255 255\n"), 0.1, {0, 0}), InputError);
  EXPECT_THROW(World::loadPgm(writeTemp("ok.pgm", "P2 1 1 255 0\n"), -0.1, {0, 0}), InputError);
}

}  // namespace
}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
