// The keypoint depth: the noise model's values, the consistency of the reported sigma with the
// error on a noisy plane, and no depth on occlusion edges, holes and the border.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "depth_model.h"

namespace plugslam::rgbd {
namespace {

constexpr double kF = 525.0, kCx = 319.5, kCy = 239.5;

// Depth of the plane n . p = d seen through a 640x480 pinhole, with axial noise from `model`.
DepthImage plane(const Eigen::Vector3d& n, double d, const DepthNoiseModel* model,
                 std::mt19937* rng) {
  DepthImage img;
  img.resize(640, 480);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int v = 0; v < img.height; ++v)
    for (int u = 0; u < img.width; ++u) {
      const Eigen::Vector3d ray((u - kCx) / kF, (v - kCy) / kF, 1.0);
      const double z = d / n.dot(ray);
      double noisy = z;
      if (model) noisy += model->sigma(z) * g(*rng);
      img.data[static_cast<size_t>(v * img.width + u)] = z > 0 ? static_cast<float>(noisy) : 0.f;
    }
  return img;
}

DepthSampling sampling() {
  DepthSampling s;
  s.focal = kF;
  return s;
}

TEST(DepthNoiseModel, KinectValues) {
  const DepthNoiseModel m;
  EXPECT_DOUBLE_EQ(m.sigma(0.4), 0.0012);
  EXPECT_NEAR(m.sigma(1.4), 0.0031, 1e-12);
  EXPECT_NEAR(m.sigma(3.4), 0.0183, 1e-12);  // Nguyen et al.: about 2 cm at 3.5 m
}

TEST(SampleDepth, SigmaIsConsistentWithTheErrorOnANoisyPlane) {
  std::mt19937 rng(7);
  const DepthSampling s = sampling();
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();  // 21 deg off head-on
  const DepthImage noisy = plane(n, 2.0, &s.noise, &rng);
  const DepthImage exact = plane(n, 2.0, nullptr, nullptr);
  double chi2 = 0;
  int count = 0;
  for (int v = 10; v < 470; v += 7)
    for (int u = 10; u < 630; u += 7) {
      const DepthSample d = sampleDepth(noisy, u, v, s);
      ASSERT_GT(d.z, 0) << u << "," << v;  // a smooth surface always ranges
      const double e = d.z - exact.at(u, v);
      chi2 += e * e / (d.sigma * d.sigma);
      ++count;
    }
  // The reported sigma adds the slope term (gradient x pixel noise, here noise-dominated) to
  // the model's: the normalised squared error averages a little under 1. Measured 0.84 over
  // 5,900 keypoints; a sigma off by 30 % either way leaves [0.6, 1.1].
  EXPECT_GT(chi2 / count, 0.6);
  EXPECT_LT(chi2 / count, 1.1);
}

TEST(SampleDepth, SlantedSurfaceRangesAndItsSlopeWidensSigma) {
  const DepthSampling s = sampling();
  // 70 degrees from head-on: the depth changes by z tan(70) / f = 1.0 cm per pixel at 2 m.
  const Eigen::Vector3d n(std::sin(70 * M_PI / 180), 0, std::cos(70 * M_PI / 180));
  const DepthImage d = plane(n, 2.0 * n.z(), nullptr, nullptr);
  const DepthSample at = sampleDepth(d, 320, 240, s);
  ASSERT_GT(at.z, 0);
  EXPECT_NEAR(at.z, d.at(320, 240), 1e-6);
  const double slope = (d.at(321, 240) - d.at(319, 240)) / 2;
  EXPECT_NEAR(at.sigma, std::hypot(s.noise.sigma(at.z), slope * s.pixel_sigma), 1e-4);
  // The slope term dominates: sigma / sigma_model = sqrt(1 + (slope / sigma_model)^2) = 2.0 here
  // (slope 1.05 cm/px, sigma_model 6.0 mm at 2 m); measured 1.99 (the Sobel slope of the 1/x
  // depth profile is a little under the central difference). 1.5 fails a slope term dropped or
  // halved.
  EXPECT_GT(at.sigma, 1.5 * s.noise.sigma(at.z));
}

TEST(SampleDepth, OcclusionEdgesHolesAndTheBorderHaveNoDepth) {
  const DepthSampling s = sampling();
  DepthImage d;
  d.resize(64, 48);
  for (int v = 0; v < d.height; ++v)
    for (int u = 0; u < d.width; ++u)
      d.data[static_cast<size_t>(v * d.width + u)] = u < 32 ? 1.0f : 1.3f;  // a box before a wall
  EXPECT_GT(sampleDepth(d, 20, 20, s).z, 0);
  EXPECT_GT(sampleDepth(d, 40, 20, s).z, 0);
  EXPECT_EQ(sampleDepth(d, 31, 20, s).z, 0);  // foreground pixel next to the background
  EXPECT_EQ(sampleDepth(d, 32, 20, s).z, 0);
  d.data[static_cast<size_t>(10 * d.width + 11)] = 0;  // a shadow next to the keypoint
  EXPECT_EQ(sampleDepth(d, 10, 10, s).z, 0);
  EXPECT_EQ(sampleDepth(d, 11, 10, s).z, 0);
  EXPECT_GT(sampleDepth(d, 13, 10, s).z, 0);
  EXPECT_EQ(sampleDepth(d, 0, 20, s).z, 0);
  EXPECT_EQ(sampleDepth(d, 63, 20, s).z, 0);
  EXPECT_EQ(sampleDepth(d, 20, 47, s).z, 0);
}

}  // namespace
}  // namespace plugslam::rgbd
