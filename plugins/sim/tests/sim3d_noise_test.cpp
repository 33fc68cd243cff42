// Sensor noise models and determinism by seed.
#include <gtest/gtest.h>

#include <cmath>

#include "sim3d/noise.h"
#include "sim3d/renderer.h"
#include "sim3d/simulator.h"
#include "sim3d/trajectory.h"

namespace plugslam::sim::sim3d {
namespace {

RenderBuffers planeAt(double distance, double tilt_deg = 0.0) {
  World w;
  const double a = tilt_deg * M_PI / 180.0;
  // A wall through (distance, 0, 0), turned by tilt_deg about the vertical.
  const Eigen::Vector3d u(std::sin(a), std::cos(a), 0.0);
  w.addQuad(Eigen::Vector3d(distance, 0.0, -200.0) - 200.0 * u, u, {0, 0, 1}, 400.0, 400.0,
            Material{}, "wall");
  RenderBuffers buf;
  render(w, PinholeCamera::vga(), lookAlong({0, 0, 0}, {1, 0, 0}), &buf, nullptr);
  return buf;
}

TEST(Sim3DNoise, DepthSigmaFollowsTheKinectModel) {
  const RenderBuffers buf = planeAt(2.0);
  DepthNoise n;
  n.quantize = false;
  n.dropout = 0.0;
  DepthImage d;
  makeDepthImage(buf, n, 7, 0, &d);
  double sum = 0, sq = 0;
  int count = 0;
  for (size_t i = 0; i < d.data.size(); ++i) {
    if (d.data[i] == 0.0f) continue;
    const double e = d.data[i] - buf.depth[i];
    sum += e;
    sq += e * e;
    ++count;
  }
  ASSERT_GT(count, 250000);
  const double sigma = 0.0012 + 0.0019 * 1.6 * 1.6;
  EXPECT_NEAR(sum / count, 0.0, 0.1 * sigma);
  EXPECT_NEAR(std::sqrt(sq / count), sigma, 0.05 * sigma);
}

TEST(Sim3DNoise, QuantisedDepthsLieOnDisparitySteps) {
  const RenderBuffers buf = planeAt(3.0);
  DepthNoise n;
  DepthImage d;
  makeDepthImage(buf, n, 1, 0, &d);
  const double bf = n.disparity_baseline * n.disparity_focal;
  int valid = 0;
  for (float z : d.data) {
    if (z == 0.0f) continue;
    ++valid;
    const double steps = bf / z * n.subpixel;
    ASSERT_NEAR(steps, std::round(steps), 1e-3);
  }
  EXPECT_GT(valid, 250000);
}

TEST(Sim3DNoise, GrazingAndFarPixelsAreMissing) {
  DepthNoise n;
  n.dropout = 0.0;
  const double cos_limit = std::cos(n.grazing_deg * M_PI / 180.0);
  // A wall turned 70 degrees away: its far side is seen at grazing angles and beyond 6 m.
  const RenderBuffers buf = planeAt(2.0, 70.0);
  DepthImage d;
  makeDepthImage(buf, n, 1, 0, &d);
  size_t grazing = 0, far = 0, valid = 0;
  for (size_t i = 0; i < d.data.size(); ++i) {
    const double z = buf.depth[i];
    const bool expect_missing =
        z == 0.0 || z < n.min_range || z > n.max_range || buf.incidence[i] < cos_limit;
    grazing += z > 0.0 && buf.incidence[i] < cos_limit;
    far += z > n.max_range;
    valid += !expect_missing;
    ASSERT_EQ(d.data[i] == 0.0f, expect_missing) << i;
  }
  EXPECT_GT(grazing, 1000u);
  EXPECT_GT(far, 1000u);
  EXPECT_GT(valid, 1000u);
  n.dropout = 0.01;
  makeDepthImage(planeAt(2.0), n, 1, 0, &d);
  size_t missing = 0;
  for (float z : d.data) missing += z == 0.0f;
  EXPECT_NEAR(static_cast<double>(missing) / d.data.size(), 0.01, 0.002);
}

TEST(Sim3DNoise, ExposureChangesSmoothlyAndIsOffWhenDisabled) {
  ImageNoise n;
  double lo = 10, hi = 0, prev = exposureGain(n, 3, 0.0), max_step = 0;
  for (int k = 1; k < 600; ++k) {
    const double g = exposureGain(n, 3, k / 30.0);
    lo = std::min(lo, g);
    hi = std::max(hi, g);
    max_step = std::max(max_step, std::abs(g - prev));
    prev = g;
  }
  EXPECT_LT(lo, 0.95);
  EXPECT_GT(hi, 1.05);
  EXPECT_LT(max_step, 0.05);
  n.enabled = false;
  EXPECT_EQ(exposureGain(n, 3, 1.7), 1.0);
}

ScenarioOptions shortRgbd(uint64_t seed) {
  ScenarioOptions o;
  o.duration = 1.0;
  o.seed = seed;
  return o;
}

TEST(Sim3DDeterminism, SameSeedSameFramesInAnyOrder) {
  const Simulator3D a = Simulator3D::fromOptions(shortRgbd(11));
  const Simulator3D b = Simulator3D::fromOptions(shortRgbd(11));
  Sim3DFrame f1, f2, other;
  a.render(5, &f1);
  b.render(7, &other);
  b.render(5, &f2);
  EXPECT_EQ(f1.left.data, f2.left.data);
  EXPECT_EQ(f1.depth.data, f2.depth.data);
  EXPECT_TRUE(f1.pose.isApprox(f2.pose, 0.0));
  a.render(5, &other);  // again, after another frame
  EXPECT_EQ(f1.left.data, other.left.data);
}

TEST(Sim3DDeterminism, AnotherSeedChangesNoiseButNotGroundTruth) {
  const Simulator3D a = Simulator3D::fromOptions(shortRgbd(1));
  const Simulator3D b = Simulator3D::fromOptions(shortRgbd(2));
  Sim3DFrame f1, f2;
  a.render(3, &f1);
  b.render(3, &f2);
  EXPECT_NE(f1.left.data, f2.left.data);
  EXPECT_NE(f1.depth.data, f2.depth.data);
  EXPECT_TRUE(f1.pose.isApprox(f2.pose, 0.0));
}

TEST(Sim3DDeterminism, NoiseOffGivesTheExactRender) {
  ScenarioOptions o = shortRgbd(4);
  o.depth_noise.enabled = false;
  o.image_noise.enabled = false;
  const Simulator3D sim = Simulator3D::fromOptions(o);
  Sim3DFrame f;
  sim.render(2, &f);
  RenderBuffers buf;
  Image image;
  image.channels = 3;
  render(sim.world(), sim.camera(), f.pose, &buf, &image);
  EXPECT_EQ(image.data, f.left.data);
  ASSERT_EQ(f.depth.data.size(), buf.depth.size());
  for (size_t i = 0; i < buf.depth.size(); ++i)
    ASSERT_EQ(f.depth.data[i], static_cast<float>(buf.depth[i]));
}

}  // namespace
}  // namespace plugslam::sim::sim3d
