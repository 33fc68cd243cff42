#include "sim2d/planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <sstream>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

std::string pointText(const Eigen::Vector2d& p) {
  std::ostringstream s;
  s << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

}  // namespace

GridPlanner::GridPlanner(const World& world, const PlannerOptions& options) : options_(options) {
  if (!(options_.resolution > 0.0)) throw InputError("sim2d planner: resolution must be positive");
  origin_ = world.boundsMin();
  const Eigen::Vector2d extent = world.boundsMax() - world.boundsMin();
  nx_ = static_cast<int>(std::ceil(extent.x() / options_.resolution)) + 1;
  ny_ = static_cast<int>(std::ceil(extent.y() / options_.resolution)) + 1;
  if (static_cast<double>(nx_) * ny_ > 2.0e7) {
    throw InputError("sim2d planner: world too large for a " + std::to_string(options_.resolution) +
                     " m grid (more than 2e7 cells); raise the planner resolution");
  }
  clearance_.resize(static_cast<size_t>(nx_) * ny_);
  const double cap = std::max(options_.preferred_clearance, options_.min_clearance);
  for (int y = 0; y < ny_; ++y) {
    for (int x = 0; x < nx_; ++x) {
      const int c = y * nx_ + x;
      clearance_[c] = world.clearance(centre(c), cap);
    }
  }
}

int GridPlanner::cellOf(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d q = (p - origin_) / options_.resolution;
  const int x = static_cast<int>(std::floor(q.x() + 0.5)),
            y = static_cast<int>(std::floor(q.y() + 0.5));
  if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return -1;
  return y * nx_ + x;
}

Eigen::Vector2d GridPlanner::centre(int cell) const {
  return origin_ + options_.resolution * Eigen::Vector2d(cell % nx_, cell / nx_);
}

double GridPlanner::cost(int cell) const {
  const double d = clearance_[cell];
  const double pref = options_.preferred_clearance;
  return 1.0 + options_.clearance_weight * std::max(0.0, (pref - d) / pref);
}

bool GridPlanner::isFree(const Eigen::Vector2d& p) const {
  const int c = cellOf(p);
  return c >= 0 && clearance_[c] >= options_.min_clearance;
}

std::vector<Eigen::Vector2d> GridPlanner::plan(const Eigen::Vector2d& from,
                                               const Eigen::Vector2d& to) const {
  const int start = cellOf(from), goal = cellOf(to);
  if (start < 0 || clearance_[start] < options_.min_clearance) {
    throw InputError("sim2d planner: start " + pointText(from) +
                     " is not in free space (closer than " +
                     std::to_string(options_.min_clearance) + " m to a wall or outside the world)");
  }
  if (goal < 0 || clearance_[goal] < options_.min_clearance) {
    throw InputError("sim2d planner: waypoint " + pointText(to) +
                     " is not in free space (closer than " +
                     std::to_string(options_.min_clearance) + " m to a wall or outside the world)");
  }
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> g(clearance_.size(), inf);
  std::vector<int> parent(clearance_.size(), -1);
  // (f, cell) pairs: ties break on the cell index, so plans are identical on every platform.
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  const Eigen::Vector2d goal_p = centre(goal);
  auto h = [&](int c) { return (centre(c) - goal_p).norm() / options_.resolution; };
  g[start] = 0.0;
  open.push({h(start), start});
  static const int dx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static const int dy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [f, c] = open.top();
    open.pop();
    if (c == goal) break;
    if (f > g[c] + h(c) + 1e-9) continue;
    const int cx = c % nx_, cy = c / nx_;
    for (int k = 0; k < 8; ++k) {
      const int x = cx + dx[k], y = cy + dy[k];
      if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
      const int n = y * nx_ + x;
      if (clearance_[n] < options_.min_clearance) continue;
      const double step = (k < 4 ? 1.0 : M_SQRT2) * 0.5 * (cost(c) + cost(n));
      if (g[c] + step < g[n]) {
        g[n] = g[c] + step;
        parent[n] = c;
        open.push({g[n] + h(n), n});
      }
    }
  }
  if (!std::isfinite(g[goal])) {
    throw InputError("sim2d planner: no collision-free path from " + pointText(from) + " to " +
                     pointText(to));
  }
  std::vector<Eigen::Vector2d> cells;
  for (int c = goal; c != -1; c = parent[c]) cells.push_back(centre(c));
  std::reverse(cells.begin(), cells.end());
  cells.front() = from;
  cells.back() = to;
  // A moving average removes the grid's staircase; a point that would leave free space keeps
  // its raw position.
  std::vector<Eigen::Vector2d> path = cells;
  const int w = 5;
  for (size_t i = 1; i + 1 < cells.size(); ++i) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int n = 0;
    for (int k = -w; k <= w; ++k) {
      const long j = static_cast<long>(i) + k;
      if (j < 0 || j >= static_cast<long>(cells.size())) continue;
      sum += cells[j];
      ++n;
    }
    const Eigen::Vector2d p = sum / n;
    if (isFree(p)) path[i] = p;
  }
  return path;
}

std::vector<Eigen::Vector2d> GridPlanner::reachable(const Eigen::Vector2d& from,
                                                    double clearance) const {
  std::vector<Eigen::Vector2d> out;
  const int start = cellOf(from);
  if (start < 0 || clearance_[start] < options_.min_clearance) return out;
  std::vector<char> seen(clearance_.size(), 0);
  std::vector<int> queue{start};
  seen[start] = 1;
  for (size_t i = 0; i < queue.size(); ++i) {
    const int c = queue[i];
    if (clearance_[c] >= clearance) out.push_back(centre(c));
    const int cx = c % nx_, cy = c / nx_;
    const int nb[4][2] = {{cx + 1, cy}, {cx - 1, cy}, {cx, cy + 1}, {cx, cy - 1}};
    for (const auto& q : nb) {
      if (q[0] < 0 || q[1] < 0 || q[0] >= nx_ || q[1] >= ny_) continue;
      const int n = q[1] * nx_ + q[0];
      if (seen[n] || clearance_[n] < options_.min_clearance) continue;
      seen[n] = 1;
      queue.push_back(n);
    }
  }
  return out;
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
