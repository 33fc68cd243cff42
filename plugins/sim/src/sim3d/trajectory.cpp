#include "sim3d/trajectory.h"

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim3d {

Eigen::Isometry3d lookAlong(const Eigen::Vector3d& position, const Eigen::Vector3d& forward) {
  const Eigen::Vector3d z = forward.normalized();
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (!(x.norm() > 1e-9)) throw InputError("sim3d lookAlong: the view direction is vertical");
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = position;
  return T;
}

Trajectory livingRoomLoop(double duration, double rate) {
  if (!(duration > 0) || !(rate > 0))
    throw InputError("sim3d livingRoomLoop: expected duration, rate > 0");
  Trajectory out;
  const int n = static_cast<int>(std::floor(duration * rate));
  for (int k = 0; k <= n; ++k) {
    const double t = k / rate;
    const double phi = 2.0 * M_PI * t / duration - 0.5 * M_PI;
    const Eigen::Vector3d p(4.0 + 1.9 * std::cos(phi), 3.0 + 1.1 * std::sin(phi),
                            1.4 + 0.08 * std::sin(3.0 * phi));
    // Outwards, turned 35 degrees along the motion, a little down, with a slow nod.
    const double yaw = phi + 0.6;
    const double pitch = -0.2 + 0.08 * std::sin(5.0 * phi);
    const Eigen::Vector3d fwd(std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch),
                              std::sin(pitch));
    out.push_back(t, lookAlong(p, fwd));
  }
  return out;
}

Trajectory driveAlong(const RoadPath& path, double height, double speed, double rate,
                      double acceleration) {
  if (path.size() < 2 || !(speed > 0) || !(rate > 0) || !(acceleration >= 0))
    throw InputError(
        "sim3d driveAlong: expected a path of two points or more, speed, rate > 0, "
        "acceleration >= 0");
  // Distance along the path after t seconds: from standing at `acceleration` up to `speed`,
  // then steady (already at speed without an acceleration).
  const double ramp = acceleration > 0 ? speed / acceleration : 0.0;
  auto travelled = [&](double t) {
    if (t < ramp) return 0.5 * acceleration * t * t;
    return 0.5 * acceleration * ramp * ramp + speed * (t - ramp);
  };
  std::vector<double> arc(path.size(), 0.0);
  for (size_t i = 1; i < path.size(); ++i) arc[i] = arc[i - 1] + (path[i] - path[i - 1]).norm();
  auto at = [&](double a) {
    a = std::clamp(a, 0.0, arc.back());
    size_t k = std::upper_bound(arc.begin(), arc.end(), a) - arc.begin();
    k = std::clamp<size_t>(k, 1, path.size() - 1);
    const double seg = arc[k] - arc[k - 1];
    const double t = seg > 0 ? (a - arc[k - 1]) / seg : 0.0;
    return Eigen::Vector3d(path[k - 1] + t * (path[k] - path[k - 1]));
  };
  Trajectory out;
  for (int k = 0;; ++k) {
    const double a = travelled(k / rate);
    if (a > arc.back()) break;
    Eigen::Vector3d fwd = at(a + 3.0) - at(a - 3.0);
    fwd.z() = 0.0;  // a level camera; the height follows the road
    out.push_back(k / rate, lookAlong(at(a) + height * Eigen::Vector3d::UnitZ(), fwd));
  }
  return out;
}

Eigen::Isometry3d livingRoomStart() { return lookAlong({3.2, 2.6, 1.5}, {-0.3, -1.0, -0.15}); }

Eigen::Isometry3d streetStart() { return lookAlong({0.0, 0.0, 1.65}, {1.0, 0.0, 0.0}); }

Trajectory anchorTrajectory(const Trajectory& trajectory, const Eigen::Isometry3d& start) {
  Trajectory out = trajectory;
  if (out.empty()) return out;
  out.transform(start * trajectory[0].pose.inverse());
  return out;
}

Trajectory panTrajectory(const Trajectory& trajectory, double amplitude, double period) {
  if (!(period > 0)) throw InputError("sim3d panTrajectory: period must be positive");
  Trajectory out;
  const double t0 = trajectory.empty() ? 0.0 : trajectory.startTime();
  for (const StampedPose& p : trajectory) {
    const double a = amplitude * std::sin(2.0 * M_PI * (p.t - t0) / period);
    Eigen::Isometry3d pose = p.pose;
    pose.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) * p.pose.linear();
    out.push_back(p.t, pose);
  }
  return out;
}

Trajectory resampleTrajectory(const Trajectory& tr, double rate) {
  if (!(rate > 0)) throw InputError("sim3d resampleTrajectory: rate must be positive");
  if (tr.size() < 2) throw InputError("sim3d resampleTrajectory: needs at least two poses");
  Trajectory out;
  const double t0 = tr.startTime(), t1 = tr.endTime();
  size_t k = 0;
  for (int i = 0;; ++i) {
    const double t = t0 + i / rate;
    if (t > t1 + 1e-9) break;
    while (k + 2 < tr.size() && tr[k + 1].t < t) ++k;
    const StampedPose &a = tr[k], &b = tr[k + 1];
    const double w = std::clamp((t - a.t) / (b.t - a.t), 0.0, 1.0);
    const Eigen::Quaterniond qa(a.pose.linear()), qb(b.pose.linear());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = qa.slerp(w, qb).normalized().toRotationMatrix();
    T.translation() = (1.0 - w) * a.pose.translation() + w * b.pose.translation();
    out.push_back(t, T);
  }
  return out;
}

RoadPath roadUnder(const Trajectory& tr, double height, double step) {
  RoadPath path;
  for (const StampedPose& p : tr) {
    const Eigen::Vector3d g = p.pose.translation() - height * Eigen::Vector3d::UnitZ();
    if (path.empty() || (g - path.back()).head<2>().norm() >= step) path.push_back(g);
  }
  if (!tr.empty()) {
    const Eigen::Vector3d g =
        tr.poses().back().pose.translation() - height * Eigen::Vector3d::UnitZ();
    if ((g - path.back()).head<2>().norm() > 1e-6) path.push_back(g);
  }
  return path;
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
