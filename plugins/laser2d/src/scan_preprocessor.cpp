#include "scan_preprocessor.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace laser2d {

void ScanPreprocessor::configure() {
  if (!mount().empty() && mount().size() != 3)
    throw ParamError("mount", "expected 3 values (x, y, theta) or an empty list, got " +
                                  std::to_string(mount().size()));
  if (max_angle() < min_angle()) throw ParamError("max_angle", "must be >= min_angle");
  if (max_range() > 0 && max_range() <= min_range())
    throw ParamError("max_range", "must be > min_range (or 0 for the scan's own)");
  if (input.name() == output.name())
    throw ParamError("output", "must differ from input '" + input.name() + "'");
}

bool ScanPreprocessor::process(Frame& frame) {
  const LaserScan* scan = input.find(frame);
  if (!scan) return false;
  PointCloud2D& cloud = output.emplace(frame);
  convert(*scan, cloud);
  return !cloud.empty();
}

void ScanPreprocessor::convert(const LaserScan& scan, PointCloud2D& out) {
  out.clear();
  const size_t n = scan.ranges.size();
  const SE2 sensor = mount().size() == 3 ? se2(mount()[0], mount()[1], mount()[2]) : scan.mount;
  out.sensor_origin = sensor.translation();
  if (n == 0) return;
  const double rmin = std::max(min_range(), scan.range_min);
  const double rmax = max_range() > 0 ? std::min(max_range(), scan.range_max) : scan.range_max;

  beam_points_.resize(n);
  valid_.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const double r = scan.ranges[i];
    const double a = scan.angle(i);
    if (!std::isfinite(r) || r <= rmin || r >= rmax || a < min_angle() || a > max_angle()) continue;
    beam_points_[i] = Eigen::Vector2d(r * std::cos(a), r * std::sin(a));
    valid_[i] = 1;
  }

  // Normals: a line fit over adjacent beams, in the sensor frame (neighbours in beam order
  // are neighbours on the surface unless the range jumps, which normal_radius rejects).
  const int k = normal_neighbors();
  const double r2_min = normal_radius() * normal_radius();
  const double spacing_per_m = normal_spacing() * std::abs(scan.angle_increment);
  const int step = decimation();
  const double min_gap2 = voxel() * voxel();
  Eigen::Vector2d last_kept(std::numeric_limits<double>::quiet_NaN(), 0.0);
  out.points.reserve(n);
  out.normals.reserve(n);
  out.weights.reserve(n);
  for (size_t i = 0; i < n; i += static_cast<size_t>(step)) {
    if (!valid_[i]) continue;
    const Eigen::Vector2d& p = beam_points_[i];
    if (voxel() > 0 && (p - last_kept).squaredNorm() < min_gap2) continue;
    const double spacing = spacing_per_m * p.norm();
    const double r2 = std::max(r2_min, spacing * spacing);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    Eigen::Matrix2d sq = Eigen::Matrix2d::Zero();
    int count = 0;
    const size_t lo = i >= static_cast<size_t>(k) ? i - k : 0;
    const size_t hi = std::min(n - 1, i + static_cast<size_t>(k));
    for (size_t j = lo; j <= hi; ++j) {
      if (!valid_[j] || (beam_points_[j] - p).squaredNorm() > r2) continue;
      const Eigen::Vector2d d = beam_points_[j] - p;  // centred on p for numerical stability
      sum += d;
      sq += d * d.transpose();
      ++count;
    }
    if (count < 3) continue;
    const Eigen::Vector2d mean = sum / count;
    const Eigen::Matrix2d cov = sq / count - mean * mean.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig;
    eig.computeDirect(cov);
    const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
    if (!(lambda(1) > 0) || lambda(0) > max_planarity() * lambda(1)) continue;
    Eigen::Vector2d normal = eig.eigenvectors().col(0);
    if (normal.dot(p) > 0) normal = -normal;  // face the sensor
    out.push(sensor * p, sensor.linear() * normal.normalized(), 1.0);
    last_kept = p;
  }
  out.touch();
}

}  // namespace laser2d
}  // namespace plugslam
