#pragma once
// Grid path planning in a sim2d World: A* over a clearance map, so planned paths keep away from
// walls (the robot drives corridor centres and door middles) and never pass closer than
// robot_radius + margin to any wall.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "sim2d/world.h"

namespace plugslam {
namespace sim {
namespace sim2d {

/// Parameters of the grid planner.
struct PlannerOptions {
  double resolution = 0.1;           ///< grid cell size [m]
  double min_clearance = 0.45;       ///< cells closer than this to a wall are blocked [m]
  double preferred_clearance = 1.1;  ///< no extra cost beyond this distance from walls [m]
  double clearance_weight = 4.0;     ///< extra cost factor when hugging walls (0 = shortest path)
};

/// A* planner on a clearance grid built once from the world.
class GridPlanner {
 public:
  /// Rasterises the world's clearance on a grid covering its bounding box.
  GridPlanner(const World& world, const PlannerOptions& options = {});

  /// A smooth collision-free path from `from` to `to` (both included). Throws InputError naming
  /// the point if either end is blocked or no path exists.
  std::vector<Eigen::Vector2d> plan(const Eigen::Vector2d& from, const Eigen::Vector2d& to) const;

  /// True if p is inside the grid and at least min_clearance from every wall.
  bool isFree(const Eigen::Vector2d& p) const;

  /// Centres of the free cells reachable from `from` whose clearance is at least `clearance`.
  std::vector<Eigen::Vector2d> reachable(const Eigen::Vector2d& from, double clearance) const;

 private:
  int cellOf(const Eigen::Vector2d& p) const;  // -1 if outside
  Eigen::Vector2d centre(int cell) const;
  double cost(int cell) const;

  PlannerOptions options_;
  Eigen::Vector2d origin_;
  int nx_ = 0, ny_ = 0;
  std::vector<double> clearance_;
};

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
