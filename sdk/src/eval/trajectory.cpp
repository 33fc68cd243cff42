#include "plugslam/trajectory.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}
}  // namespace

Trajectory::Trajectory(std::vector<StampedPose> poses) {
  poses_.reserve(poses.size());
  for (const StampedPose& p : poses) push_back(p.t, p.pose);
}

void Trajectory::push_back(double t, const Eigen::Isometry3d& pose) {
  if (!std::isfinite(t)) throw InputError("trajectory timestamp is not a finite number");
  if (!pose.matrix().allFinite())
    throw InputError("trajectory pose at t=" + num(t) + " has a non-finite entry");
  if (!poses_.empty() && t <= poses_.back().t) {
    throw InputError("trajectory timestamps must increase: " + num(t) + " comes after " +
                     num(poses_.back().t));
  }
  poses_.push_back(StampedPose{t, pose});
}

double Trajectory::startTime() const {
  if (poses_.empty()) throw InputError("the trajectory is empty");
  return poses_.front().t;
}

double Trajectory::endTime() const {
  if (poses_.empty()) throw InputError("the trajectory is empty");
  return poses_.back().t;
}

double Trajectory::pathLength() const {
  const std::vector<double> d = cumulativeDistances();
  return d.empty() ? 0.0 : d.back();
}

std::vector<double> Trajectory::cumulativeDistances() const {
  std::vector<double> d(poses_.size(), 0.0);
  for (std::size_t i = 1; i < poses_.size(); ++i) {
    d[i] = d[i - 1] + (poses_[i].pose.translation() - poses_[i - 1].pose.translation()).norm();
  }
  return d;
}

std::optional<std::size_t> Trajectory::nearest(double t, double max_dt) const {
  if (poses_.empty()) return std::nullopt;
  auto it = std::lower_bound(poses_.begin(), poses_.end(), t,
                             [](const StampedPose& p, double v) { return p.t < v; });
  std::size_t best = poses_.size();
  double best_dt = max_dt;
  auto consider = [&](std::size_t i) {
    const double dt = std::abs(poses_[i].t - t);
    if (dt <= best_dt) {
      best_dt = dt;
      best = i;
    }
  };
  const auto i = static_cast<std::size_t>(it - poses_.begin());
  if (i < poses_.size()) consider(i);
  if (i > 0) consider(i - 1);
  if (best == poses_.size()) return std::nullopt;
  return best;
}

void Trajectory::transform(const Eigen::Isometry3d& T) {
  for (StampedPose& p : poses_) p.pose = T * p.pose;
}

}  // namespace abi_v1
}  // namespace plugslam
