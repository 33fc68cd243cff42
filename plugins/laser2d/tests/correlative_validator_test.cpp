// CorrelativeValidator: recovers a loop closure far from the guess, rejects a wrong place and an
// ambiguous corridor.
#include "correlative_validator.h"

#include <gtest/gtest.h>

#include <chrono>

#include "point_map_slice.h"
#include "scan_preprocessor.h"
#include "synthetic.h"

namespace plugslam::laser2d {
namespace {

// A local map whose origin is `origin` (world frame) built from scans at the world poses `robots`.
LocalMap makeMap(const std::vector<test::Segment>& world, const SE2& origin,
                 const std::vector<SE2>& robots, double range_max, uint32_t seed) {
  ScanPreprocessor pre;
  pre.configure();
  PointMapSlice slice;
  slice.configure();
  LocalMap map;
  map.origin = Space2D::to3D(origin);
  for (const SE2& robot : robots) {
    test::ScanSpec spec;
    spec.noise = 0.01;
    spec.seed = seed++;
    spec.range_max = range_max;
    Frame frame;
    frame.raw.set("front_laser", test::castScan(world, robot, spec));
    pre.process(frame);
    slice.merge(frame, map.scene, origin.inverse() * robot);
  }
  return map;
}

// Expects `v` to reject `query` as the place of `candidate` near `guess`, for a reason that
// names `why`.
void expectRejected(CorrelativeValidator& v, const LocalMap& candidate, const LocalMap& query,
                    const SE2& guess, const std::string& why) {
  LoopClosure closure;
  std::string reason;
  EXPECT_FALSE(v.validate(candidate, query, Space2D::to3D(guess), closure, reason));
  EXPECT_NE(reason.find(why), std::string::npos) << reason;
  std::cout << reason << "\n";
}

double elapsedMs(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

TEST(CorrelativeValidator, RecoversALoopFarFromTheGuess) {
  const auto world = test::building();
  const SE2 c_origin = se2(3, 3, 0.2), q_origin = se2(4, 2.5, -0.5);
  const LocalMap candidate =
      makeMap(world, c_origin, {se2(3, 3, 0.2), se2(3.5, 3.2, 0.4), se2(4, 3.5, 0.6)}, 30, 1);
  const LocalMap query = makeMap(world, q_origin, {se2(4, 2.5, -0.5), se2(4.4, 2.7, -0.3)}, 30, 9);
  const SE2 truth = c_origin.inverse() * q_origin;
  const Eigen::Vector3d t = toVector(truth);
  const SE2 guess = se2(t.x() - 2.5, t.y() + 1.8, t.z() - 0.4);

  CorrelativeValidator v;
  v.configure();
  LoopClosure closure;
  std::string reason;
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(v.validate(candidate, query, Space2D::to3D(guess), closure, reason)) << reason;
  const double ms = elapsedMs(t0);
  const Eigen::Vector3d found = toVector(Space2D::from3D(closure.edge.relative));
  const double points = static_cast<double>(query.scene.get<PointCloud2D>("front").size());
  std::cout << "query points " << points << ", score " << closure.overlap << ", error "
            << (found.head<2>() - t.head<2>()).norm() << " m, " << std::abs(found.z() - t.z())
            << " rad, " << ms << " ms\n";
  EXPECT_LT((found.head<2>() - t.head<2>()).norm(), v.resolution());
  const double step = 1 / std::sqrt(closure.edge.information(2, 2));
  EXPECT_LT(std::abs(found.z() - t.z()), step);
  EXPECT_GE(closure.overlap, v.min_score());
  ASSERT_EQ(closure.edge.information.rows(), 3);
  EXPECT_NEAR(closure.edge.information(0, 0), 1 / (0.05 * 0.05), 1e-9);
  EXPECT_GT(closure.edge.information(2, 2), 0.0);
  EXPECT_EQ(closure.edge.information(0, 1), 0.0);
}

TEST(CorrelativeValidator, RejectsADifferentPlace) {
  const auto world = test::building();
  const LocalMap candidate =
      makeMap(world, se2(3, 3, 0), {se2(3, 3, 0), se2(3.5, 3.2, 0.4)}, 30, 1);
  // A round-ish hall of another shape: walls at other distances and angles.
  std::vector<test::Segment> other;
  const int sides = 7;
  for (int i = 0; i < sides; ++i) {
    const double a0 = 2 * M_PI * i / sides, a1 = 2 * M_PI * (i + 1) / sides;
    other.push_back({{5 * std::cos(a0), 5 * std::sin(a0)}, {5 * std::cos(a1), 5 * std::sin(a1)}});
  }
  for (const auto& s : test::box(1, 1, 1.5, 2.5)) other.push_back(s);
  const LocalMap query = makeMap(other, se2(0, 0, 0), {se2(0, 0, 0), se2(0.5, -0.3, 0.2)}, 30, 5);

  CorrelativeValidator v;
  v.configure();
  expectRejected(v, candidate, query, se2(1, 0, 0), "no pose scores");
}

TEST(CorrelativeValidator, RejectsAnAmbiguousCorridor) {
  // A long corridor whose ends are out of range: any shift along it fits as well.
  const auto world = test::corridor(-60, 60, 1.0);
  const LocalMap candidate =
      makeMap(world, se2(0, 0, 0), {se2(-1, 0, 0), se2(0, 0.2, 0.1), se2(1, 0, -0.1)}, 12, 1);
  const LocalMap query = makeMap(world, se2(2, 0, 0), {se2(2, 0, 0), se2(2.5, 0.1, 0.1)}, 12, 7);
  CorrelativeValidator v;
  v.configure();
  expectRejected(v, candidate, query, se2(0.5, 0.3, 0.2), "ambiguous");

  // Without the margin test the same search accepts a pose on the corridor's axis.
  v.min_score_margin = 0.0;
  v.configure();
  LoopClosure closure;
  std::string reason;
  ASSERT_TRUE(v.validate(candidate, query, Space2D::to3D(se2(0.5, 0.3, 0.2)), closure, reason))
      << reason;
  const Eigen::Vector3d found = toVector(Space2D::from3D(closure.edge.relative));
  EXPECT_LT(std::abs(found.y()), 0.1);
  EXPECT_LT(std::abs(found.z()), 0.05);
}

}  // namespace
}  // namespace plugslam::laser2d
