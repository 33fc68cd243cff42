#include "sim2d/laser.h"

#include <cmath>
#include <limits>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim2d {

void LaserConfig::validate() const {
  const std::string who = "sim2d laser '" + name + "': ";
  if (name.empty()) throw InputError("sim2d laser: expected a non-empty name");
  if (!mount.allFinite()) throw InputError(who + "mount must be finite (x, y, yaw)");
  if (!(fov > 0.0 && fov <= 2.0 * M_PI)) throw InputError(who + "fov must be in (0, 2*pi] rad");
  if (beams < 1 || beams > 1000000) throw InputError(who + "beams must be in [1, 1000000]");
  if (!(min_range >= 0.0)) throw InputError(who + "min_range must be >= 0");
  if (!(max_range > min_range) || !std::isfinite(max_range)) {
    throw InputError(who + "max_range must be finite and greater than min_range");
  }
  if (!(range_sigma >= 0.0)) throw InputError(who + "range_sigma must be >= 0");
  if (!(dropout >= 0.0 && dropout <= 1.0)) throw InputError(who + "dropout must be in [0, 1]");
}

void simulateScan(const World& world, const Eigen::Vector3d& robot_pose, const LaserConfig& config,
                  Rng* rng, LaserScan* scan) {
  scan->name = config.name;
  scan->angle_min = config.angleMin();
  scan->angle_increment = config.angleIncrement();
  scan->min_range = config.min_range;
  scan->max_range = config.max_range;
  scan->mount = config.mount;
  scan->ranges.resize(config.beams);

  const double c = std::cos(robot_pose.z()), s = std::sin(robot_pose.z());
  const Eigen::Vector2d origin(robot_pose.x() + c * config.mount.x() - s * config.mount.y(),
                               robot_pose.y() + s * config.mount.x() + c * config.mount.y());
  const double heading = robot_pose.z() + config.mount.z();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < config.beams; ++i) {
    const double a = heading + scan->angle_min + i * scan->angle_increment;
    double r = world.castRay(origin, Eigen::Vector2d(std::cos(a), std::sin(a)), config.max_range);
    if (rng) {
      // Draw in a fixed order for every beam so one beam's outcome never shifts the others'.
      const bool dropped = rng->bernoulli(config.dropout);
      const double noise = rng->gaussian(config.range_sigma);
      if (dropped) r = nan;
      r += noise;
    }
    scan->ranges[i] =
        (std::isfinite(r) && r >= config.min_range && r <= config.max_range) ? r : nan;
  }
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
