#include "sim2d/simulator.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

void requirePositive(double v, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) {
    throw InputError(std::string("sim2d simulator: ") + what + " must be a positive number");
  }
}

double polylineLength(const std::vector<Eigen::Vector2d>& p) {
  double len = 0.0;
  for (size_t i = 1; i < p.size(); ++i) len += (p[i] - p[i - 1]).norm();
  return len;
}

void append(std::vector<Eigen::Vector2d>& path, const std::vector<Eigen::Vector2d>& leg) {
  for (const Eigen::Vector2d& q : leg) {
    if (path.empty() || (q - path.back()).norm() > 1e-9) path.push_back(q);
  }
}

}  // namespace

Eigen::Isometry2d toIsometry(const Eigen::Vector3d& pose) {
  Eigen::Isometry2d t = Eigen::Isometry2d::Identity();
  t.linear() = Eigen::Rotation2Dd(pose.z()).toRotationMatrix();
  t.translation() = pose.head<2>();
  return t;
}

Simulator::Simulator(SimConfig config) : config_(std::move(config)) {
  if (!config_.world) throw InputError("sim2d simulator: expected a world");
  requirePositive(config_.path_length, "path_length");
  requirePositive(config_.rate, "rate");
  if (config_.substeps < 1 || config_.substeps > 1000) {
    throw InputError("sim2d simulator: substeps must be in [1, 1000]");
  }
  const DriveLimits& d = config_.drive;
  requirePositive(d.max_linear, "drive.max_linear");
  requirePositive(d.max_angular, "drive.max_angular");
  requirePositive(d.max_linear_acc, "drive.max_linear_acc");
  requirePositive(d.max_angular_acc, "drive.max_angular_acc");
  requirePositive(d.lookahead, "drive.lookahead");
  requirePositive(d.wheel_base, "drive.wheel_base");
  if (!(d.robot_radius >= 0.0))
    throw InputError("sim2d simulator: drive.robot_radius must be >= 0");
  if (config_.tour.empty()) throw InputError("sim2d simulator: expected at least one tour place");
  std::set<std::string> names;
  for (const LaserConfig& l : config_.lasers) {
    l.validate();
    if (!names.insert(l.name).second) {
      throw InputError("sim2d simulator: two lasers are named '" + l.name +
                       "'; names must be unique");
    }
  }
  const OdometryNoise& n = config_.odometry;
  for (double v : {n.left_scale_error, n.right_scale_error, n.wheel_base_error}) {
    if (!(v > -0.5 && v < 0.5))
      throw InputError("sim2d simulator: odometry scale errors must be in (-0.5, 0.5)");
  }
  if (!(n.slip_per_distance >= 0.0) || !(n.slip_per_rotation >= 0.0)) {
    throw InputError("sim2d simulator: odometry slip must be >= 0");
  }
  buildTrajectory();
  reset();
}

void Simulator::buildTrajectory() {
  const World& world = *config_.world;
  const GridPlanner planner(world, config_.planner);
  // Plan a little more than needed: corner cutting makes the driven path shorter than planned.
  const double needed = 1.2 * config_.path_length + 5.0;
  planned_.clear();
  if (config_.tour.size() >= 2) {
    std::vector<Eigen::Vector2d> cycle;
    const auto& t = config_.tour;
    for (size_t i = 0; i < t.size(); ++i) append(cycle, planner.plan(t[i], t[(i + 1) % t.size()]));
    const double cycle_len = polylineLength(cycle);
    if (cycle_len < 1e-6)
      throw InputError("sim2d simulator: the tour places are all the same point");
    while (polylineLength(planned_) < needed) append(planned_, cycle);
  } else {
    // Exploration: random reachable goals with good clearance, at least 4 m apart.
    Rng rng(config_.seed, 2);
    const Eigen::Vector2d start = config_.tour.front();
    const std::vector<Eigen::Vector2d> goals = planner.reachable(start, 0.8);
    if (goals.empty()) {
      throw InputError(
          "sim2d simulator: nothing reachable with 0.8 m clearance from the start place");
    }
    Eigen::Vector2d at = start;
    planned_.push_back(start);
    double length = 0.0;
    int attempts = 0;
    while (length < needed) {
      if (++attempts > 100000)
        throw InputError("sim2d simulator: exploration found no goals 4 m apart");
      const Eigen::Vector2d g = goals[rng.index(goals.size())];
      if ((g - at).norm() < 4.0) continue;
      const std::vector<Eigen::Vector2d> leg = planner.plan(at, g);
      length += polylineLength(leg);
      append(planned_, leg);
      at = g;
    }
  }

  PurePursuit follower(planned_, config_.drive);
  const double b = config_.drive.wheel_base;
  const double dt = 1.0 / (config_.rate * config_.substeps);
  // Initial heading: towards the planned path half a metre ahead.
  size_t ahead = 1;
  while (ahead + 1 < planned_.size() && (planned_[ahead] - planned_[0]).norm() < 0.5) ++ahead;
  const Eigen::Vector2d dir = planned_[ahead] - planned_[0];
  Eigen::Vector3d pose(planned_[0].x(), planned_[0].y(), std::atan2(dir.y(), dir.x()));

  ground_truth_.assign(1, pose);
  wheels_.clear();
  path_length_ = 0.0;
  min_clearance_ = world.clearance(pose.head<2>(), 1e9);
  const double max_frames =
      100.0 * config_.rate * config_.path_length / config_.drive.max_linear + 1e4;
  while (path_length_ < config_.path_length) {
    const Eigen::Vector3d frame_start = pose;
    for (int k = 0; k < config_.substeps; ++k) {
      const Eigen::Vector2d cmd = follower.command(pose, dt);
      const double dl = (cmd.x() - 0.5 * b * cmd.y()) * dt;
      const double dr = (cmd.x() + 0.5 * b * cmd.y()) * dt;
      const Eigen::Vector3d next = driveArc(pose, dl, dr, b);
      path_length_ += (next.head<2>() - pose.head<2>()).norm();
      wheels_.emplace_back(dl, dr);
      pose = next;
    }
    if (world.crosses(frame_start.head<2>(), pose.head<2>())) {
      std::ostringstream m;
      m << "sim2d simulator: the robot would cross a wall near (" << pose.x() << ", " << pose.y()
        << ") at frame " << ground_truth_.size() << "; move the tour places away from walls";
      throw InputError(m.str());
    }
    min_clearance_ = std::min(min_clearance_, world.clearance(pose.head<2>(), 1e9));
    ground_truth_.push_back(pose);
    if (follower.finished() || ground_truth_.size() > max_frames) {
      throw InputError(
          "sim2d simulator: the robot could not complete the tour (stuck or the path "
          "ended early); check that the tour places are reachable");
    }
  }
}

void Simulator::reset() {
  next_ = 0;
  odometry_ = std::make_unique<WheelOdometry>(ground_truth_.front(), config_.drive.wheel_base,
                                              config_.odometry, config_.seed);
  laser_rngs_.clear();
  for (size_t i = 0; i < config_.lasers.size(); ++i)
    laser_rngs_.emplace_back(config_.seed, 100 + i);
}

bool Simulator::step(SimFrame& frame) {
  if (next_ >= ground_truth_.size()) return false;
  frame.index = next_;
  frame.time = static_cast<double>(next_) / config_.rate;
  frame.ground_truth = ground_truth_[next_];
  frame.wheel_left = frame.wheel_right = 0.0;
  if (next_ > 0) {
    const size_t first = (next_ - 1) * config_.substeps;
    for (int k = 0; k < config_.substeps; ++k) {
      const Eigen::Vector2d& w = wheels_[first + k];
      const Eigen::Vector2d measured = odometry_->update(w.x(), w.y());
      frame.wheel_left += measured.x();
      frame.wheel_right += measured.y();
    }
  }
  frame.odometry = odometry_->pose();
  frame.lasers.resize(config_.lasers.size());
  for (size_t i = 0; i < config_.lasers.size(); ++i) {
    simulateScan(*config_.world, frame.ground_truth, config_.lasers[i], &laser_rngs_[i],
                 &frame.lasers[i]);
  }
  ++next_;
  return true;
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
