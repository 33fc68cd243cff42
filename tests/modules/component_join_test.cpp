// ComponentJoin: loops between components whose relative pose is unknown are held until loops
// from several query maps agree on it; loops that disagree (a look-alike, a tracker's jump) join
// nothing; a robot localizing inside the saved maps needs one.
#include "modules/graph/component_join.h"

#include <gtest/gtest.h>

#include "plugslam/pose_space.h"

namespace plugslam {
namespace {

// Component 0: maps 0..3 in the world; component 4: maps 4..7 in a frame of their own, placed at
// `frame` in the world (unknown to the join), 2 m of path apart.
struct TwoComponents {
  GraphView view;
  std::vector<Eigen::Isometry3d> truth;
  explicit TwoComponents(const Eigen::Isometry3d& frame) {
    for (int i = 0; i < 8; ++i) {
      Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
      t.translate(Eigen::Vector3d(2.0 * (i % 4), 0.5 * i, 0));
      t.rotate(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()));
      truth.push_back(t);
      view.origins.push_back(i < 4 ? t : frame.inverse() * t);
      view.travelled.push_back(2.0 * i);
      view.components.push_back(i < 4 ? 0 : 4);
    }
  }
  // The loop from map `older` to map `query` as a validator would measure it (off by `error`).
  GraphEdge loop(int64_t older, int64_t query,
                 const Eigen::Isometry3d& error = Eigen::Isometry3d::Identity()) const {
    GraphEdge e;
    e.from = older;
    e.to = query;
    e.loop = true;
    e.relative = truth[static_cast<size_t>(older)].inverse() * truth[static_cast<size_t>(query)] *
                 error;
    return e;
  }
};

Eigen::Isometry3d moved(double x, double y, double yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(x, y, 0));
  t.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return t;
}

const Eigen::Isometry3d kFrame = moved(20, -7, 1.2);

TEST(ComponentJoin, HoldsALoopUntilAnotherPlaceAgrees) {
  const TwoComponents s(kFrame);
  detail::ComponentJoin join;
  const detail::JoinRule rule;
  std::vector<std::pair<int, int>> joined;
  EXPECT_TRUE(join.decide(s.view, s.loop(1, 5), rule, joined).empty());
  // Another loop of the same query map is the same place: still held.
  EXPECT_TRUE(join.decide(s.view, s.loop(2, 5), rule, joined).empty());
  const auto added = join.decide(s.view, s.loop(2, 6), rule, joined);
  EXPECT_EQ(added.size(), 3u);  // the new loop and the two it agrees with
  ASSERT_EQ(joined.size(), 1u);
  EXPECT_EQ(joined[0], std::make_pair(0, 4));
  // Joined in this view: later loops between them pass.
  EXPECT_EQ(join.decide(s.view, s.loop(3, 7), rule, joined).size(), 1u);
}

TEST(ComponentJoin, LoopsThatDisagreeJoinNothing) {
  const TwoComponents s(kFrame);
  detail::ComponentJoin join;
  const detail::JoinRule rule;
  std::vector<std::pair<int, int>> joined;
  // A look-alike: the second loop is 3 m off where the first puts the components.
  EXPECT_TRUE(join.decide(s.view, s.loop(1, 5), rule, joined).empty());
  EXPECT_TRUE(join.decide(s.view, s.loop(2, 6, moved(3, 0, 0)), rule, joined).empty());
  // ...or turned 0.2 rad (more than 0.05 rad + 0.01 rad/m over 2 m).
  EXPECT_TRUE(join.decide(s.view, s.loop(0, 6, moved(0, 0, 0.2)), rule, joined).empty());
  EXPECT_TRUE(joined.empty());
  // A third place agrees with the first: those two join, not the look-alikes.
  const auto added = join.decide(s.view, s.loop(3, 7), rule, joined);
  ASSERT_EQ(added.size(), 2u);
  EXPECT_EQ(added[1].to, 5);
}

TEST(ComponentJoin, TheToleranceGrowsWithThePathBetweenThePlaces) {
  TwoComponents s(kFrame);
  const detail::JoinRule rule;
  // 0.6 m off: beyond 0.5 m two metres apart (0.6 m allowed), within it twenty metres apart.
  for (double apart : {2.0, 20.0}) {
    s.view.travelled[6] = s.view.travelled[5] + apart;
    detail::ComponentJoin join;
    std::vector<std::pair<int, int>> joined;
    EXPECT_TRUE(join.decide(s.view, s.loop(1, 5), rule, joined).empty());
    const auto added = join.decide(s.view, s.loop(2, 6, moved(0.65, 0, 0)), rule, joined);
    EXPECT_EQ(added.size(), apart > 10 ? 2u : 0u) << apart << " m apart";
  }
}

TEST(ComponentJoin, ALocalizingRobotJoinsTheSavedMapsWithOneLoop) {
  TwoComponents s(kFrame);
  s.view.localizing = true;
  detail::ComponentJoin join;
  std::vector<std::pair<int, int>> joined;
  EXPECT_EQ(join.decide(s.view, s.loop(1, 5), detail::JoinRule{}, joined).size(), 1u);
}

TEST(ComponentJoin, ALoopWithinAComponentPasses) {
  const TwoComponents s(kFrame);
  detail::ComponentJoin join;
  std::vector<std::pair<int, int>> joined;
  EXPECT_EQ(join.decide(s.view, s.loop(1, 3), detail::JoinRule{}, joined).size(), 1u);
  EXPECT_TRUE(joined.empty());
}

}  // namespace
}  // namespace plugslam
