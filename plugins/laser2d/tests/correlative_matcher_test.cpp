// CorrelativeGrid: the pooled levels bound the base grid, and every point's cell is a full hit.
#include "correlative_matcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

}  // namespace
}  // namespace plugslam::laser2d
