// CorrelativeGrid: the pooled levels bound the base grid, and every point's cell is a full hit.
#include "correlative_matcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace plugslam::laser2d {
namespace {

TEST(CorrelativeGrid, PooledLevelsBoundTheBase) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 200; ++i) points.emplace_back(0.037 * i, std::sin(0.1 * i));
  const CorrelativeGrid grid(points, {}, 0.0, 0.05, 4, Eigen::Vector2d(-100, -100),
                             Eigen::Vector2d(100, 100));
  ASSERT_EQ(grid.levels(), 4);
  EXPECT_EQ(grid.value(0, -1, 0), 0);
  EXPECT_EQ(grid.value(0, grid.width(), 0), 0);
  for (int h = 1; h <= 4; ++h) {
    const int s = 1 << h;
    for (int y = -s; y < grid.height(); y += 3)
      for (int x = -s; x < grid.width(); x += 3) {
        int m = 0;
        for (int dy = 0; dy < s; ++dy)
          for (int dx = 0; dx < s; ++dx) m = std::max(m, grid.value(0, x + dx, y + dy));
        ASSERT_EQ(grid.value(h, x, y), m) << h << " " << x << " " << y;
      }
  }
  // Every point's own cell is a full hit.
  for (const auto& p : points) {
    const Eigen::Vector2d c = (p - grid.origin()) / grid.resolution();
    EXPECT_EQ(
        grid.value(0, static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y()))),
        255);
  }
}

// A grid given its base values and a non-zero `outside` (a map's unknown space): the pooled
// levels take the outside into account where their windows leave the grid, and a scorer's sum
// is the points' cells' values whether the query lies wholly inside a level or reaches out of it.
TEST(CorrelativeGrid, PoolingAndScoringAgreeWithTheCellsOutsideToo) {
  const int w = 23, h = 17;
  std::vector<uint8_t> base(static_cast<size_t>(w) * h);
  for (size_t i = 0; i < base.size(); ++i) base[i] = static_cast<uint8_t>((i * 37) % 251);
  const CorrelativeGrid grid(0.1, Eigen::Vector2d(-1.0, -0.5), w, h, base, 3, 60);
  for (int l = 1; l <= 3; ++l) {
    const int s = 1 << l;
    for (int y = -s - 1; y < h + 1; ++y)
      for (int x = -s - 1; x < w + 1; ++x) {
        int m = 0;
        for (int dy = 0; dy < s; ++dy)
          for (int dx = 0; dx < s; ++dx) m = std::max(m, grid.value(0, x + dx, y + dy));
        ASSERT_EQ(grid.value(l, x, y), m) << l << " " << x << " " << y;
      }
  }
  const std::vector<Eigen::Vector2d> query = {{0.0, 0.0}, {0.33, 0.12}, {-0.2, 0.41}, {0.05, -0.3}};
  SearchLattice<Space2D> lattice;
  lattice.resolution = 0.1;
  lattice.angular_step = 0.1;
  lattice.angles = 2;
  const GridScorer scorer(grid, query, lattice);
  const double r = grid.resolution();
  for (int a = -2; a <= 2; ++a) {
    const Eigen::Rotation2Dd rot(a * 0.1);
    for (int l = 0; l <= 3; ++l)
      for (int y = -12; y <= 12; ++y)
        for (int x = -14; x <= 14; ++x) {
          int sum = 0;
          for (const auto& q : query) {
            const Eigen::Vector2d p = rot * q - grid.origin();
            sum += grid.value(l, static_cast<int>(std::floor(p.x() / r)) + x,
                              static_cast<int>(std::floor(p.y() / r)) + y);
          }
          ASSERT_DOUBLE_EQ(scorer.score(l, a, x, y), sum / 255.0) << l << " " << x << " " << y;
        }
  }
}

// A room with an inner wall (no symmetry): its wall points and their normals.
void roomOf(std::vector<Eigen::Vector2d>& room, std::vector<Eigen::Vector2d>& normals) {
  for (int i = 0; i < 200; ++i) {
    const double t = -5 + 0.05 * i;
    room.emplace_back(t, 3.0), normals.emplace_back(0, -1);
    room.emplace_back(t, -2.0), normals.emplace_back(0, 1);
    if (i < 100) room.emplace_back(4.0, -2 + 0.05 * i), normals.emplace_back(-1, 0);
    if (i < 40) room.emplace_back(1.0 + 0.05 * i, 0.5), normals.emplace_back(0, 1);
  }
}

// A room seen from `truth` (every third wall point) and a search of +-`cells` cells (0.1 m) and
// +-`angles` heading steps (0.02 rad) around the origin, with its grid and scorer.
struct RoomSearch {
  RoomSearch(const SE2& truth, int cells, int angles) {
    roomOf(room, normals);
    for (size_t i = 0; i < room.size(); i += 3) scan.push_back(truth.inverse() * room[i]);
    lattice.resolution = 0.1;
    lattice.angular_step = 0.02;
    lattice.cells = cells;
    lattice.angles = angles;
    lattice.levels = searchLevels(lattice.cells);
    const Eigen::Vector2d reach(12, 12);
    grid = std::make_unique<CorrelativeGrid>(room, normals, 0.1, lattice.resolution, lattice.levels,
                                             -reach, reach);
    scorer = std::make_unique<GridScorer>(*grid, scan, lattice);
  }
  // The best of score - penalty(a, x, y) over every lattice pose, and that pose.
  template <class Penalty>
  double exhaustiveBest(Penalty penalty, SE2& pose) const {
    double best = -1e9;
    for (int a = -lattice.angles; a <= lattice.angles; ++a)
      for (int x = -lattice.cells; x <= lattice.cells; ++x)
        for (int y = -lattice.cells; y <= lattice.cells; ++y)
          if (scorer->score(0, a, x, y) - penalty(a, x, y) > best) {
            best = scorer->score(0, a, x, y) - penalty(a, x, y);
            pose = lattice.pose(a, x, y);
          }
    return best;
  }
  std::vector<Eigen::Vector2d> room, normals, scan;
  SearchLattice<Space2D> lattice;
  std::unique_ptr<CorrelativeGrid> grid;
  std::unique_ptr<GridScorer> scorer;
};

// The branch and bound of the SDK's correlative search finds the pose an exhaustive scoring of
// every lattice pose finds (its bounds never prune the best), on a room seen from a guess that is
// off in translation and heading.
TEST(CorrelativeSearch, BranchAndBoundFindsTheExhaustiveBest) {
  const SE2 truth = se2(0.3, -0.2, 0.16);  // on the lattice
  const RoomSearch room(truth, 6, 12);
  SE2 best_pose = SE2::Identity();
  const double best = room.exhaustiveBest([](int, int, int) { return 0.0; }, best_pose);
  SearchOptions o;
  o.min_score = 0.1;
  o.ambiguity_margin = 0;
  const SearchResult<Space2D> found =
      correlativeSearch<Space2D>({room.scorer.get()}, room.lattice, o);
  ASSERT_TRUE(found.found);
  EXPECT_NEAR(found.score * room.scorer->maxScore(), best, 1e-9);
  EXPECT_LT((found.pose.translation() - truth.translation()).norm(), 0.11);
  EXPECT_NEAR(std::atan2(found.pose.linear()(1, 0), found.pose.linear()(0, 0)), 0.16, 0.021);
  EXPECT_LT((best_pose.translation() - found.pose.translation()).norm(), 1e-9);
}

// Over a full turn the lattice's first and last headings are neighbours: a room seen turned by
// nearly pi is found unambiguous, not rivalled by itself one heading step across the seam.
TEST(CorrelativeSearch, AFullTurnHasNoSeam) {
  std::vector<Eigen::Vector2d> room, normals;
  roomOf(room, normals);
  SearchLattice<Space2D> lattice;
  lattice.center = se2(0, 0, 0);
  lattice.resolution = 0.1;
  lattice.angular_step = 0.02;
  lattice.cells = 6;
  lattice.angles = static_cast<int>(std::ceil(M_PI / lattice.angular_step));
  lattice.levels = searchLevels(lattice.cells);
  const SE2 truth = lattice.pose(lattice.angles - 1, 3, -2);  // one step short of the seam
  std::vector<Eigen::Vector2d> scan;
  for (size_t i = 0; i < room.size(); i += 3) scan.push_back(truth.inverse() * room[i]);
  const Eigen::Vector2d reach(12, 12);
  const CorrelativeGrid grid(room, normals, 0.1, lattice.resolution, lattice.levels, -reach, reach);
  const GridScorer scorer(grid, scan, lattice);
  // The pose across the seam scores nearly as the best: it is the same heading.
  ASSERT_GT(scorer.score(0, -lattice.angles, 3, -2),
            0.8 * scorer.score(0, lattice.angles - 1, 3, -2));
  SearchOptions o;
  o.min_score = 0.5;
  o.ambiguity_margin = 0.05;
  const SearchResult<Space2D> found = correlativeSearch<Space2D>({&scorer}, lattice, o);
  ASSERT_TRUE(found.found);
  EXPECT_FALSE(found.ambiguous) << "rival " << found.rival_score << " vs " << found.score;
  EXPECT_LT((found.pose.translation() - truth.translation()).norm(), 0.11);
}

// Two peaks at heading 0: `near` at the center's cell, `far` 20 cells along x; a coarser node
// bounds by the best peak it holds.
class TwoPeaks : public LatticeScorer {
 public:
  TwoPeaks(double near, double far) : near_(near), far_(far) {}
  double score(int level, int a, int x, int y) const override {
    if (a != 0) return 0;
    const int size = 1 << level;
    const auto holds = [&](int px) { return x <= px && px < x + size && y <= 0 && 0 < y + size; };
    return std::max(holds(0) ? near_ : 0.0, holds(20) ? far_ : 0.0);
  }
  double maxScore() const override { return 100; }

 private:
  double near_, far_;
};

// The motion prior in the search's score: a look-alike 2 m away (4 sigma of the typical error)
// that fits a little better loses to the pose at the prediction; one that fits clearly better
// (by more than prior_margin, the most the capped prior takes) wins.
TEST(CorrelativeSearch, ThePriorFavoursThePredictionUpToItsMargin) {
  SearchLattice<Space2D> lattice;
  lattice.resolution = 0.1;
  lattice.angular_step = 0.05;
  lattice.cells = 30;
  lattice.angles = 4;
  lattice.levels = searchLevels(lattice.cells);
  SearchOptions o;
  o.min_score = 0.5;
  o.ambiguity_margin = 0;
  const auto found_x = [&](const TwoPeaks& scorer) {
    const SearchResult<Space2D> r = correlativeSearch<Space2D>({&scorer}, lattice, o);
    EXPECT_TRUE(r.found);
    return r.pose.translation().x();
  };
  const TwoPeaks slightly(90, 95), clearly(85, 100);
  EXPECT_NEAR(found_x(slightly), 2.0, 1e-9);  // the scores alone: the better fit
  o.prior_margin = 0.1;
  o.prior_translation = 1 / (0.5 * 0.5);
  o.prior_rotation = 1 / (0.2 * 0.2);
  o.prior_cap = 9;
  EXPECT_NEAR(found_x(slightly), 0.0, 1e-9);
  EXPECT_NEAR(found_x(clearly), 2.0, 1e-9);
}

// With the prior, branch and bound still finds the exhaustive best of score - penalty.
TEST(CorrelativeSearch, BranchAndBoundWithThePriorFindsTheExhaustiveBest) {
  const RoomSearch room(se2(0.4, -0.3, 0.1), 8, 10);
  SearchOptions o;
  o.min_score = 0.1;
  o.ambiguity_margin = 0;
  o.prior_margin = 0.3;
  o.prior_translation = 1 / (0.2 * 0.2);
  o.prior_rotation = 1 / (0.05 * 0.05);
  o.prior_cap = 9;
  const double total = room.scorer->maxScore();
  // A lattice pose's nearest point to the center: half a step closer on each axis.
  const auto g = [](int i) { return std::max(0.0, std::abs(i) - 0.5); };
  SE2 pose = SE2::Identity();
  const double best = room.exhaustiveBest(
      [&](int a, int x, int y) {
        const double m2 = (g(x) * g(x) + g(y) * g(y)) * 0.01 * o.prior_translation +
                          g(a) * g(a) * 0.02 * 0.02 * o.prior_rotation;
        return total * o.prior_margin * std::min(m2, 9.0) / 9.0;
      },
      pose);
  const SearchResult<Space2D> found =
      correlativeSearch<Space2D>({room.scorer.get()}, room.lattice, o);
  ASSERT_TRUE(found.found);
  EXPECT_NEAR(found.score * total, best, 1e-6);
}

}  // namespace
}  // namespace plugslam::laser2d
