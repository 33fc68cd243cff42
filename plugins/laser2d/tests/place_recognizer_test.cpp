// PlaceRecognizer: finds a place of a second component whose frame has nothing to do with the
// first's; proposes nothing for look-alike rooms or a place the other component never saw. (That
// several loops agree before components join is the graph's: tests/modules/component_join_test.)
#include "place_recognizer.h"

#include <gtest/gtest.h>

#include "synthetic_maps.h"

namespace plugslam::laser2d {
namespace {

// Robot A mapped `a` (world poses, component 0); robot B then drove `b`, whose estimates are in
// its own frame: the world seen from `b_frame` (component 1, ids after A's).
struct TwoRobots {
  GraphView view;
  std::vector<SE2> truth;
  TwoRobots(const std::vector<test::Segment>& world, const std::vector<SE2>& a,
            const std::vector<test::Segment>& world_b, const std::vector<SE2>& b,
            const SE2& b_frame, double b_spacing = 2.5) {
    for (size_t i = 0; i < a.size(); ++i) add(world, a[i], a[i], 0, 2.0 * i);
    for (size_t i = 0; i < b.size(); ++i)
      add(world_b, b[i], b_frame.inverse() * b[i], 1, 1e6 + b_spacing * i);
  }
  void add(const std::vector<test::Segment>& world, const SE2& t, const SE2& estimate,
           int component, double travelled) {
    const auto id = static_cast<int64_t>(view.maps.size());
    // Two scans, at the place and a little ahead; the map where its component's frame has it.
    auto m = test::mapOfScans(id, world, t, {t, t * se2(0.3, 0.05, 0.1)},
                              static_cast<uint32_t>(10 * id + 1));
    m->origin = Space2D::to3D(estimate);
    view.maps.push_back(m);
    view.origins.push_back(m->origin);
    view.travelled.push_back(travelled);
    view.components.push_back(component);
    truth.push_back(t);
  }
};

const std::vector<SE2> kRobotA = {se2(2, 2, 0.1), se2(3, 5, 0.3), se2(9, 5, 0.5), se2(12, 4, 1.0)};
const std::vector<SE2> kRobotB = {se2(4, 8, 2.0), se2(3, 3, -1.0), se2(11, 2, 0.4)};
const SE2 kFrameB = se2(20, -7, 1.2);  // B's frame in A's: unknown to the detector

TEST(PlaceRecognizer, ProposesTheMapsWhereItFoundThePlace) {
  const TwoRobots s(test::building(), kRobotA, test::building(), kRobotB, kFrameB);
  PlaceRecognizer d;
  d.configure();
  for (int64_t q : {4, 5}) {
    const auto found = d.detect(s.view, *s.view.maps[static_cast<size_t>(q)]);
    ASSERT_EQ(found.size(), static_cast<size_t>(d.max_candidates())) << "query " << q;
    for (const LoopCandidate& c : found) {
      EXPECT_TRUE(c.matched && c.global);
      EXPECT_LT(c.id, 4);  // a map of A's
      const Eigen::Vector3d want = toVector(s.truth[c.id].inverse() * s.truth[q]);
      const Eigen::Vector3d got = toVector(Space2D::from3D(c.relative));
      // Exact on the search's lattice: within a cell or two and a few angular steps.
      EXPECT_LT((got.head<2>() - want.head<2>()).norm(), 2 * d.resolution()) << "map " << c.id;
      EXPECT_LT(std::abs(got.z() - want.z()), 0.03) << "map " << c.id;
    }
  }
}

TEST(PlaceRecognizer, ProposesNothingInAGraphOfOneComponent) {
  TwoRobots s(test::building(), kRobotA, test::building(), kRobotB, kFrameB);
  std::fill(s.view.components.begin(), s.view.components.end(), 0);
  PlaceRecognizer d;
  d.configure();
  for (int64_t q = 4; q < 7; ++q) EXPECT_TRUE(d.detect(s.view, *s.view.maps[q]).empty());
}

TEST(PlaceRecognizer, ProposesNothingBetweenLookAlikeRooms) {
  // Two identical rooms far apart: every match in one fits the other as well.
  std::vector<test::Segment> twins = test::box(0, 0, 7, 4);
  for (const auto& seg : test::box(30, 0, 37, 4)) twins.push_back(seg);
  for (const auto& seg : test::box(2, 1, 2.6, 1.5)) twins.push_back(seg);
  for (const auto& seg : test::box(32, 1, 32.6, 1.5)) twins.push_back(seg);
  const TwoRobots s(twins, {se2(4, 2.5, 0), se2(34, 2.5, 0)}, twins,
                    {se2(5, 2, 0.5), se2(4, 3, -0.3), se2(5.5, 2.2, 1.0)}, kFrameB);
  PlaceRecognizer d;
  d.configure();
  for (int64_t q = 2; q < 5; ++q) EXPECT_TRUE(d.detect(s.view, *s.view.maps[q]).empty());
}

TEST(PlaceRecognizer, ProposesNothingForAPlaceTheOtherComponentNeverSaw) {
  std::vector<test::Segment> hall;  // seven sides and a pillar: nothing of the building fits it
  const int sides = 7;
  for (int i = 0; i < sides; ++i) {
    const double a0 = 2 * M_PI * i / sides, a1 = 2 * M_PI * (i + 1) / sides;
    hall.push_back({{7 + 5 * std::cos(a0), 5 + 5 * std::sin(a0)},
                    {7 + 5 * std::cos(a1), 5 + 5 * std::sin(a1)}});
  }
  for (const auto& seg : test::box(8, 6, 8.5, 7.5)) hall.push_back(seg);
  const TwoRobots s(test::building(), kRobotA, hall,
                    {se2(7, 5, 0.2), se2(6, 4, 1.0), se2(8, 4, -0.5)}, kFrameB);
  PlaceRecognizer d;
  d.configure();
  for (int64_t q = 4; q < 7; ++q) EXPECT_TRUE(d.detect(s.view, *s.view.maps[q]).empty());
}

}  // namespace
}  // namespace plugslam::laser2d
