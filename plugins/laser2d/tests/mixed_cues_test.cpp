// Issue 16: a planar laser and a camera in one Multi-Aligner, on a synthetic hall where each cue
// is weak where the other is strong. The laser's long walls fix the lateral position and the
// heading but say little along the hall (a few door jambs only); a camera looking sideways at the
// textured far wall fixes the position along it by bearing, but measures the distance to the wall
// only through a depth whose noise grows with the square of it. One solve over both cues'
// factors, each weighted by its own noise model, must beat either cue alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_slices.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/property_container.h"
#include "scan_preprocessor.h"
#include "scan_slices.h"
#include "synthetic.h"

namespace plugslam::laser2d {
namespace {

// A hall along x, 5 m wide, with door jambs (10 cm deep) every few metres in its near wall: the
// laser's only hold along it. Its end walls are beyond the scanner's range.
std::vector<test::Segment> hall() {
  std::vector<test::Segment> w = {{{-30, -1}, {30, -1}}, {{-30, 4}, {30, 4}}};
  for (double x : {-4.0, 3.0, 7.5}) {
    w.push_back({{x, -1}, {x, -0.9}});
    w.push_back({{x, -0.9}, {x + 0.1, -0.9}});
    w.push_back({{x + 0.1, -0.9}, {x + 0.1, -1}});
  }
  return w;
}

// Textured points on the hall's far wall, each with its own random 256-bit descriptor.
struct Texture {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<uint8_t, 32>> descriptors;
};

Texture texture(std::mt19937& rng) {
  Texture t;
  std::uniform_real_distribution<double> x(-6.0, 6.0), z(0.1, 2.4);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < 120; ++i) {
    t.points.emplace_back(x(rng), 4.0, z(rng));
    std::array<uint8_t, 32> d;
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    t.descriptors.push_back(d);
  }
  return t;
}

// A camera 1 m up, looking to the robot's left (optical z along its y axis, x right, y down).
Eigen::Isometry3d cameraMount() {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear().col(0) = Eigen::Vector3d::UnitX();
  m.linear().col(1) = -Eigen::Vector3d::UnitZ();
  m.linear().col(2) = Eigen::Vector3d::UnitY();
  m.translation() = Eigen::Vector3d(0.1, 0.0, 1.0);
  return m;
}

// What the camera sees from `robot`: each textured point in view as a keypoint with 1 px of
// noise and a Kinect-like depth noise (1.5 mm at 1 m, growing with the square of the depth).
FeatureSet observe(const Texture& tex, const SE2& robot, std::mt19937& rng) {
  FeatureSet f;
  f.camera = PinholeCamera{525.0, 525.0, 319.5, 239.5, 0.0};
  f.width = 640;
  f.height = 480;
  f.mount = cameraMount();
  const Eigen::Isometry3d world_to_camera = (Space2D::to3D(robot) * f.mount).inverse();
  std::normal_distribution<double> n(0.0, 1.0);
  const double sigma_px = 1.0;
  for (size_t i = 0; i < tex.points.size(); ++i) {
    const Eigen::Vector3d c = world_to_camera * tex.points[i];
    if (c.z() < 0.5 || c.z() > 8.0) continue;
    const Eigen::Vector2d uv(f.camera.fx * c.x() / c.z() + f.camera.cx,
                             f.camera.fy * c.y() / c.z() + f.camera.cy);
    if (uv.x() < 0 || uv.y() < 0 || uv.x() > 639 || uv.y() > 479) continue;
    const double sigma_z = 0.0015 * c.z() * c.z();
    f.pushDepth(uv + sigma_px * Eigen::Vector2d(n(rng), n(rng)), sigma_px,
                c.z() + sigma_z * n(rng), sigma_z, tex.descriptors[i].data(), 0x808080);
  }
  return f;
}

PointCloud2D cloudOf(const LaserScan& scan) {
  ScanPreprocessor pre;
  pre.configure();
  PointCloud2D cloud;
  pre.convert(scan, cloud);
  return cloud;
}

struct Errors {
  double translation = 0, rotation = 0;  // RMS over the trials [m], [rad]
  int invalid = 0;
};

// Aligns a frame at `truth` against a scene built from a noisy view at the origin, `trials`
// times with fresh noise, with the laser, the camera or both, from a guess 3.6 cm and 0.6 deg off.
Errors alignTrials(bool laser, bool camera, int trials) {
  const auto world = hall();
  std::mt19937 rng(11);
  const Texture tex = texture(rng);
  const SE2 truth = se2(0.4, 0.05, 0.03);
  test::ScanSpec spec;
  spec.beams = 540;
  spec.fov = 1.5 * M_PI;
  spec.range_max = 12.0;
  spec.noise = 0.01;
  Errors e;
  for (int k = 0; k < trials; ++k) {
    PropertyContainer scene;
    Frame frame;
    spec.seed = static_cast<uint32_t>(2 * k + 1);
    scene.set("front", cloudOf(test::castScan(world, SE2::Identity(), spec)));
    spec.seed = static_cast<uint32_t>(2 * k + 2);
    frame.measurement.set("front", cloudOf(test::castScan(world, truth, spec)));
    Frame reference;
    reference.measurement.set<FeatureSet>("features", observe(tex, SE2::Identity(), rng));
    LandmarkMapSlice<Space2D> merger;
    merger.configure();
    merger.merge(reference, scene, SE2::Identity());
    frame.measurement.set<FeatureSet>("features", observe(tex, truth, rng));

    MultiAligner<Space2D> aligner;
    if (laser) aligner.slices.assign(std::make_shared<PointToLineSlice>());
    if (camera) {
      auto slice = std::make_shared<ReprojectionSlice<Space2D>>();
      slice->landmark_uncertainty = true;
      slice->configure();
      aligner.slices.assign(slice);
    }
    aligner.configure();
    const SE2 guess = truth * se2(0.03, -0.02, 0.01);
    const AlignResult<Space2D> r = aligner.align(frame, scene, {SE2::Identity(), guess});
    if (!r.valid) {
      ++e.invalid;
      continue;
    }
    const Eigen::Vector3d d = toVector(SE2(truth.inverse() * r.pose));
    e.translation += d.head<2>().squaredNorm();
    e.rotation += d.z() * d.z();
  }
  const int valid = trials - e.invalid;
  e.translation = std::sqrt(e.translation / std::max(valid, 1));
  e.rotation = std::sqrt(e.rotation / std::max(valid, 1));
  return e;
}

TEST(MixedCues, LaserAndCameraInOneSolveBeatEitherAlone) {
  const int trials = 30;
  const Errors laser = alignTrials(true, false, trials);
  const Errors camera = alignTrials(false, true, trials);
  const Errors both = alignTrials(true, true, trials);
  for (const auto& [name, e] : {std::pair<const char*, Errors>{"laser", laser},
                                {"camera", camera},
                                {"laser + camera", both}})
    std::printf("%-15s translation %.4f m, rotation %.3f deg RMS (%d invalid of %d)\n", name,
                e.translation, e.rotation * 180 / M_PI, e.invalid, trials);
  // Each cue alone aligns: the test compares accuracies, not a cue that fails.
  EXPECT_EQ(laser.invalid, 0);
  EXPECT_EQ(camera.invalid, 0);
  EXPECT_EQ(both.invalid, 0);
  // Issue 16's mixed-world target, here where the noise models are exact: together at most
  // 0.8 times the better cue's error.
  EXPECT_LT(both.translation, 0.8 * std::min(laser.translation, camera.translation));
  // The heading is the laser's strength (its walls are 5 m long, the camera's bearings span
  // less): together it stays the laser's, within what 30 trials resolve (an RMS over 30 samples
  // is uncertain by about 13 %). Measured: translation 6.8 cm, 1.3 cm, 2.5 mm; heading 0.012,
  // 0.157, 0.014 deg (laser, camera, both).
  EXPECT_LT(both.rotation, 1.3 * std::min(laser.rotation, camera.rotation));
}

}  // namespace
}  // namespace plugslam::laser2d
