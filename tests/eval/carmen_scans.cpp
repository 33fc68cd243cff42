#include "carmen_scans.h"

#include <zlib.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace plugslam::test {

CarmenScans readCarmenScans(const std::string& path, double max_range) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open " + path);
  CarmenScans out;
  std::string line;
  char buf[1 << 16];
  int index = 0;
  while (gzgets(f, buf, sizeof(buf))) {
    line = buf;
    if (line.rfind("FLASER ", 0) != 0) continue;
    std::istringstream ss(line.substr(7));
    int n = 0;
    ss >> n;
    std::vector<double> r(static_cast<std::size_t>(n));
    for (double& v : r) ss >> v;
    double x, y, theta;
    ss >> x >> y >> theta;
    if (!ss) {
      gzclose(f);
      throw std::runtime_error("bad FLASER line in " + path);
    }
    const double step = (n == 180 || n == 181) ? M_PI / 180 : M_PI / 360;
    PosedScan s;
    for (int k = 0; k < n; ++k) {
      const double range = r[static_cast<std::size_t>(k)];
      if (!(range > 0.0) || range >= max_range) continue;
      const double a = -M_PI / 2 + step * k;
      s.points.emplace_back(range * std::cos(a), range * std::sin(a));
    }
    s.pose = Eigen::Isometry2d::Identity();
    s.pose.linear() = Eigen::Rotation2Dd(theta).toRotationMatrix();
    s.pose.translation() = Eigen::Vector2d(x, y);
    out.scans.push_back(std::move(s));
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(x, y, 0.0);
    out.poses.push_back(index, p);
    ++index;
  }
  gzclose(f);
  return out;
}

}  // namespace plugslam::test
