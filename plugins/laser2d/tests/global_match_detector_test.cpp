// GlobalMatchDetector: finds a revisit metres and a radian away from the estimate, proposes
// nothing for a place the candidate never saw; its grid scores hits, free and unknown space.
#include "global_match_detector.h"

#include <gtest/gtest.h>

#include "synthetic_maps.h"

namespace plugslam::laser2d {
namespace {

// Three candidate maps along a short path, then (30 m of path later) the query map.
struct Scenario {
  GraphView view;
  SE2 query_truth;
  void add(const std::shared_ptr<LocalMap>& m, double travelled) {
    view.maps.push_back(m);
    view.origins.push_back(m->origin);
    view.travelled.push_back(travelled);
  }
};

Scenario revisit(const std::vector<test::Segment>& query_world, const SE2& query_truth,
                 const SE2& query_estimate) {
  const auto world = test::building();
  Scenario s;
  const SE2 c[3] = {se2(2, 2, 0.1), se2(3, 2.3, 0.3), se2(4, 2.8, 0.5)};
  for (int i = 0; i < 3; ++i)
    s.add(test::mapOfScans(i, world, c[i], {c[i], c[i] * se2(0.4, 0, 0.1)}, 10 * i + 1), 1.0 * i);
  auto q = test::mapOfScans(3, query_world, query_truth, {query_truth, query_truth * se2(0.4, 0.1, -0.1)},
                   77);
  q->origin = Space2D::to3D(query_estimate);  // where the drifted estimate has it
  s.add(q, 32.0);
  s.query_truth = query_truth;
  return s;
}

TEST(GlobalMatchDetector, FindsARevisitFarFromTheEstimate) {
  // The truth is 3.9 m and 1.1 rad away from the estimate: far outside a proximity gate.
  const SE2 truth = se2(4, 5.5, 2.6);
  const Scenario s = revisit(test::building(), truth, truth * se2(2.5, -3.0, 1.1));
  GlobalMatchDetector d;
  d.configure();
  const auto found = d.detect(s.view, *s.view.maps[3]);
  ASSERT_EQ(found.size(), 1u);
  const LoopCandidate& c = found[0];
  EXPECT_TRUE(c.matched);
  EXPECT_GE(c.score, d.min_score());
  const Eigen::Vector3d want = toVector(Space2D::from3D(s.view.origins[c.id]).inverse() * truth);
  const Eigen::Vector3d got = toVector(Space2D::from3D(c.relative));
  // Exact on the search's lattice: within a cell and a couple of angular steps.
  EXPECT_LT((got.head<2>() - want.head<2>()).norm(), d.resolution());
  EXPECT_LT(std::abs(got.z() - want.z()), 0.02);
}

TEST(GlobalMatchDetector, ProposesNothingForAPlaceItNeverSaw) {
  // A seven-sided hall with a pillar: no pose of its scans fits the building's walls.
  std::vector<test::Segment> other;
  const int sides = 7;
  for (int i = 0; i < sides; ++i) {
    const double a0 = 2 * M_PI * i / sides, a1 = 2 * M_PI * (i + 1) / sides;
    other.push_back({{7 + 5 * std::cos(a0), 5 + 5 * std::sin(a0)},
                     {7 + 5 * std::cos(a1), 5 + 5 * std::sin(a1)}});
  }
  for (const auto& seg : test::box(8, 6, 8.5, 7.5)) other.push_back(seg);
  const Scenario s = revisit(other, se2(7, 5, 0.2), se2(6, 4, 0.5));
  GlobalMatchDetector d;
  d.configure();
  EXPECT_TRUE(d.detect(s.view, *s.view.maps[3]).empty());
}

TEST(GlobalMatchDetector, WaitsWhileLoopsKeepClosing) {
  const SE2 truth = se2(4, 5.5, 2.6);
  Scenario s = revisit(test::building(), truth, truth * se2(0.5, 0.2, 0.1));
  GlobalMatchDetector d;
  d.configure();
  s.view.last_loop_travelled = 30.0;  // 2 m of path ago: the proximity detector is coping
  EXPECT_TRUE(d.detect(s.view, *s.view.maps[3]).empty());
  s.view.last_loop_travelled = 20.0;
  EXPECT_EQ(d.detect(s.view, *s.view.maps[3]).size(), 1u);
}

TEST(GlobalMatchDetector, GridScoresHitsFreeAndUnknownSpace) {
  PlacedCloud wall;  // a wall 5 m ahead of the origin, seen from the origin
  for (int i = -10; i <= 10; ++i) {
    wall.points.emplace_back(5.0, 0.1 * i);
    wall.normals.emplace_back(-1.0, 0.0);
  }
  const uint8_t unknown = 77;
  const MatchGrid g = rasterizeClouds({wall}, 0.1, 3, unknown);
  const auto cell = [&](double x, double y) {
    const Eigen::Vector2d q = (Eigen::Vector2d(x, y) - g.grid->origin()) / 0.1;
    return Eigen::Vector2i(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())));
  };
  const auto value = [&](double x, double y) {
    const Eigen::Vector2i c = cell(x, y);
    return g.grid->value(0, c.x(), c.y());
  };
  EXPECT_EQ(value(5.0, 0.0), 255);        // on the wall
  EXPECT_EQ(value(2.55, 0.05), 0);        // crossed by the rays: free
  EXPECT_EQ(value(2.55, 3.05), unknown);  // beside the rays' fan: never seen
  EXPECT_EQ(value(-30, 0), unknown);      // outside the grid
  EXPECT_TRUE(g.isObserved(cell(2.55, 0.05).x(), cell(2.55, 0.05).y()));
  EXPECT_FALSE(g.isObserved(cell(2.55, 3.05).x(), cell(2.55, 3.05).y()));
  // The pooled levels bound the base from above, unknown included.
  EXPECT_EQ(g.grid->levels(), 3);
  const Eigen::Vector2i c = cell(2.55, 3.05);
  EXPECT_GE(g.grid->value(3, c.x() - 7, c.y() - 7), unknown);
}

}  // namespace
}  // namespace plugslam::laser2d
