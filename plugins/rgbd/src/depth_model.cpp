#include "depth_model.h"

#include <cmath>

namespace plugslam {
namespace rgbd {

DepthNoiseParams::DepthNoiseParams(Configurable* owner)
    : a{owner, "depth_sigma_a", 0.0012, "m",
        "depth noise sigma(z) = a + b (z - z0)^2: a (Kinect v1, Nguyen et al. 2012)",
        Range{0, 10}},
      b{owner, "depth_sigma_b", 0.0019, "1/m", "depth noise growth b (Kinect v1: 1.9 mm/m^2)",
        Range{0, 10}},
      z0{owner, "depth_sigma_z0", 0.4, "m", "depth noise z0 (Kinect v1: its 0.4 m minimum range)",
         Range{0, 100}} {}

DepthNoiseModel DepthNoiseParams::model() const {
  DepthNoiseModel m;
  m.a = a();
  m.b = b();
  m.z0 = z0();
  return m;
}

DepthSample sampleDepth(const DepthImage& depth, int x, int y, const DepthSampling& s) {
  if (x < 1 || y < 1 || x + 1 >= depth.width || y + 1 >= depth.height) return {};
  const double z = depth.at(x, y);
  if (!(z > 0)) return {};
  const double sigma = s.noise.sigma(z);
  // Two independent readings differ by up to 3 sqrt(2) sigma by noise alone.
  const double noise_gate = 3.0 * std::sqrt(2.0) * sigma;
  const double slope = z * s.tan_max_incidence / s.focal;  // [m/px] on the steepest surface
  double n[3][3];
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const double v = depth.at(x + dx, y + dy);
      if (!(v > 0)) return {};
      const double distance = (dx != 0 && dy != 0) ? std::sqrt(2.0) : 1.0;
      if (std::abs(v - z) > noise_gate + slope * distance) return {};
      n[dy + 1][dx + 1] = v;
    }
  }
  // Sobel gradient [m/px]: a keypoint off by sigma_px on the slope reads another depth.
  const double gx = ((n[0][2] + 2 * n[1][2] + n[2][2]) - (n[0][0] + 2 * n[1][0] + n[2][0])) / 8;
  const double gy = ((n[2][0] + 2 * n[2][1] + n[2][2]) - (n[0][0] + 2 * n[0][1] + n[0][2])) / 8;
  const double position = std::sqrt(gx * gx + gy * gy) * s.pixel_sigma;
  return {z, std::sqrt(sigma * sigma + position * position)};
}

}  // namespace rgbd
}  // namespace plugslam
