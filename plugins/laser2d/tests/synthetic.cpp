#include "synthetic.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace plugslam::laser2d::test {

std::vector<Segment> box(double x0, double y0, double x1, double y1) {
  return {{{x0, y0}, {x1, y0}}, {{x1, y0}, {x1, y1}}, {{x1, y1}, {x0, y1}}, {{x0, y1}, {x0, y0}}};
}

std::vector<Segment> room(double w, double h) {
  std::vector<Segment> out = box(0, 0, w, h);
  for (const auto& s : box(0.25 * w, 0.6 * h, 0.25 * w + 0.4, 0.6 * h + 0.3)) out.push_back(s);
  for (const auto& s : box(0.7 * w, 0.2 * h, 0.7 * w + 0.3, 0.2 * h + 0.5)) out.push_back(s);
  return out;
}

std::vector<Segment> building() {
  std::vector<Segment> w = box(0, 0, 14, 10);
  w.push_back({{6, 0}, {6, 4}});
  w.push_back({{6, 5.2}, {6, 10}});
  for (const auto& s : box(2, 6.5, 3, 7.2)) w.push_back(s);
  for (const auto& s : box(9.5, 2, 10.1, 3.4)) w.push_back(s);
  for (const auto& s : box(11, 7, 12.5, 7.4)) w.push_back(s);
  w.push_back({{0, 3}, {1.5, 3}});
  return w;
}

std::vector<Segment> corridor(double x0, double x1, double half_width) {
  return {{{x0, -half_width}, {x1, -half_width}},
          {{x0, half_width}, {x1, half_width}},
          {{x1, -half_width}, {x1, half_width}}};
}

LaserScan castScan(const std::vector<Segment>& world, const SE2& robot, const ScanSpec& spec) {
  LaserScan scan;
  scan.angle_min = -spec.fov / 2;
  scan.angle_increment = spec.beams > 1 ? spec.fov / (spec.beams - 1) : 0.0;
  scan.range_min = 0.05;
  scan.range_max = spec.range_max;
  scan.mount = spec.mount;
  scan.ranges.resize(spec.beams);
  std::mt19937 rng(spec.seed);
  std::normal_distribution<double> noise(0.0, spec.noise > 0 ? spec.noise : 1.0);
  const SE2 sensor = robot * spec.mount;
  const Eigen::Vector2d o = sensor.translation();
  for (int i = 0; i < spec.beams; ++i) {
    const double a = angleOf(sensor.linear()) + scan.angle(i);
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = std::numeric_limits<double>::infinity();
    for (const auto& s : world) {
      // o + t d = a + u (b - a)
      const Eigen::Vector2d e = s.b - s.a;
      const double den = d.x() * (-e.y()) - d.y() * (-e.x());
      if (std::abs(den) < 1e-12) continue;
      const Eigen::Vector2d w = s.a - o;
      const double t = (w.x() * (-e.y()) - w.y() * (-e.x())) / den;
      const double u = (d.x() * w.y() - d.y() * w.x()) / den;
      if (t > 1e-9 && u >= 0 && u <= 1 && t < best) best = t;
    }
    if (spec.noise > 0 && std::isfinite(best)) best += noise(rng);
    scan.ranges[i] = best < spec.range_max ? best : std::numeric_limits<double>::infinity();
  }
  return scan;
}

double distanceToSegment(const Eigen::Vector2d& p, const Segment& s) {
  const Eigen::Vector2d e = s.b - s.a;
  const double u = std::clamp((p - s.a).dot(e) / e.squaredNorm(), 0.0, 1.0);
  return (s.a + u * e - p).norm();
}

}  // namespace plugslam::laser2d::test
