// Local bundle adjustment: landmarks placed from one noisy stereo observation each, and frames
// whose poses were tracked with an error, settle on what all of the observations say.
#include "plugslam/landmarks/local_bundle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "plugslam/geometry.h"
#include "plugslam/landmarks/observation_factor.h"
#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/optimizer.h"
#include "plugslam/solver/robust_kernel.h"

namespace plugslam {
namespace {

PinholeCamera camera() { return {700, 700, 620, 188, 0.54}; }

struct Scene {
  std::vector<Eigen::Vector3d> points;   // the truth, in the map's frame
  std::vector<Eigen::Isometry3d> poses;  // the truth: a camera driving 1 m a frame along +z
};

Scene scene(std::mt19937& rng) {
  Scene s;
  std::uniform_real_distribution<double> x(-12, 12), y(-3, 3), z(6, 40);
  for (int i = 0; i < 300; ++i) s.points.emplace_back(x(rng), y(rng), z(rng));
  for (int k = 0; k < 8; ++k) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(0.05 * k * k, 0.0, 1.0 * k);
    p.linear() = Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d::UnitY()).toRotationMatrix();
    s.poses.push_back(p);
  }
  return s;
}

double meanError(const LandmarkMap& map, const Scene& s) {
  double sum = 0;
  for (size_t j = 0; j < map.size(); ++j) sum += (map.positions[j] - s.points[map.ids[j]]).norm();
  return sum / static_cast<double>(map.size());
}

// The frames' observations of the scene (every third without depth, when `some_without_depth`),
// each landmark placed where the first frame that saw it measured it; the frames between the
// first and the last tracked 10-20 cm and a few mrad off.
std::vector<BundleFrame> observe(const Scene& s, std::mt19937& rng, LandmarkMap& map,
                                 bool some_without_depth) {
  const PinholeCamera c = camera();
  const double sigma_px = 0.5, sigma_d = 0.3;  // pixels, disparity pixels
  std::normal_distribution<double> npx(0, sigma_px), nd(0, sigma_d);
  std::vector<BundleFrame> frames;
  for (size_t k = 0; k < s.poses.size(); ++k) {
    BundleFrame f;
    f.seq = k;
    f.camera = c;
    f.pose = s.poses[k];
    for (size_t i = 0; i < s.points.size(); ++i) {
      const Eigen::Vector3d pc = s.poses[k].inverse() * s.points[i];
      if (pc.z() < 1) continue;
      const double u = c.fx * pc.x() / pc.z() + c.cx + npx(rng);
      const double v = c.fy * pc.y() / pc.z() + c.cy + npx(rng);
      if (u < 0 || v < 0 || u > 1240 || v > 375) continue;
      const double d = c.fx * c.baseline / pc.z() + nd(rng);
      if (d <= 0) continue;
      const double q = d / (c.fx * c.baseline);
      const double sigma_q = sigma_d / (c.fx * c.baseline);
      const bool depth = !some_without_depth || (i + k) % 3 != 0;
      f.observations.push_back(
          BundleObservation{i, Eigen::Vector3d(u, v, depth ? q : 0.0),
                            Eigen::Vector3d(1 / (sigma_px * sigma_px), 1 / (sigma_px * sigma_px),
                                            depth ? 1 / (sigma_q * sigma_q) : 0.0)});
      // A landmark is placed where the first frame that saw it measured it.
      bool known = false;
      for (uint64_t id : map.ids) known = known || id == i;
      if (!known) {
        const double z = 1 / q;
        const Eigen::Vector3d measured((u - c.cx) / c.fx * z, (v - c.cy) / c.fy * z, z);
        uint8_t descriptor[32] = {};
        map.push(s.poses[k] * measured, Eigen::Matrix3d::Identity(), i, descriptor, 0, k);
      }
    }
    frames.push_back(std::move(f));
  }
  for (size_t k = 1; k + 1 < frames.size(); ++k) {
    Vector6d off;
    off << 0.1, -0.05, 0.15, 0.003, -0.004, 0.002;
    frames[k].pose = frames[k].pose * se3(off);
  }
  return frames;
}

TEST(LocalBundle, RefinesLandmarksAndTheFramesBetweenTheFixedOnes) {
  std::mt19937 rng(3);
  const Scene s = scene(rng);
  LandmarkMap map;
  std::vector<BundleFrame> frames = observe(s, rng, map, false);
  frames.front().fixed = frames.back().fixed = true;
  const double before = meanError(map, s);
  const BundleResult r = adjustBundle(frames, map);
  EXPECT_EQ(r.frames, 8);
  EXPECT_GT(r.landmarks, 100);
  EXPECT_LT(r.chi2_after, r.chi2_before);
  const double after = meanError(map, s);
  // Far points placed from one disparity are metres off; eight views bring them to a fraction.
  EXPECT_LT(after, 0.5 * before) << before << " -> " << after;
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Isometry3d e = s.poses[k].inverse() * frames[k].pose;
    EXPECT_LT(e.translation().norm(), 0.03) << "frame " << k;
    EXPECT_LT(Eigen::AngleAxisd(e.linear()).angle(), 1e-3) << "frame " << k;
  }
  EXPECT_TRUE(frames.front().pose.isApprox(s.poses.front()));
  EXPECT_TRUE(frames.back().pose.isApprox(s.poses.back()));
}

// The bundle eliminates the landmarks to solve for the poses alone: it must reach the optimum the
// SDK's general sparse solver reaches on the same factors (one fixed frame, the rest free, some
// observations without depth).
TEST(LocalBundle, ReachesTheOptimumOfTheGeneralSolver) {
  std::mt19937 rng(5);
  const Scene s = scene(rng);
  LandmarkMap map;
  std::vector<BundleFrame> frames = observe(s, rng, map, true);
  frames.front().fixed = true;

  FactorGraph graph;
  std::vector<VariableSE3*> poses;
  for (size_t k = 0; k < frames.size(); ++k) {
    poses.push_back(&graph.addVariable<VariableSE3>(static_cast<int64_t>(k), frames[k].pose));
    poses.back()->setFixed(frames[k].fixed);
  }
  std::vector<VariablePoint3*> points(s.points.size(), nullptr);
  std::vector<int> seen(s.points.size(), 0);
  for (const BundleFrame& f : frames)
    for (const BundleObservation& o : f.observations) ++seen[o.landmark];
  for (size_t j = 0; j < map.size(); ++j)
    if (seen[map.ids[j]] >= 2)
      points[map.ids[j]] = &graph.addVariable<VariablePoint3>(
          static_cast<int64_t>(frames.size() + j), map.positions[j]);
  const std::shared_ptr<const RobustKernel> kernel = makeRobustKernel("huber", 2.0);
  for (size_t k = 0; k < frames.size(); ++k)
    for (const BundleObservation& o : frames[k].observations) {
      if (!points[o.landmark]) continue;
      auto& f = graph.emplaceFactor<LandmarkObservationFactor>(
          poses[k], points[o.landmark], o.measured, frames[k].camera, frames[k].mount);
      f.setInformation(o.information.asDiagonal());
      f.setRobustKernel(kernel);
    }
  OptimizerOptions oo;
  oo.max_iterations = 50;
  oo.relative_decrease = 1e-12;
  oo.gauge = GaugeMode::kNone;
  Optimizer(oo).optimize(graph);

  BundleOptions options;
  options.iterations = 50;
  const BundleResult r = adjustBundle(frames, map, options);
  // Both stop when an iteration lowers the cost by less than a millionth: the same cost, and
  // estimates as near as that flat a cost pins them.
  EXPECT_NEAR(r.chi2_after, graph.robustChi2(), 1e-6 * r.chi2_after);
  for (size_t k = 0; k < frames.size(); ++k) {
    const Eigen::Isometry3d e = poses[k]->estimate().inverse() * frames[k].pose;
    EXPECT_LT(e.translation().norm(), 1e-4) << "frame " << k;
    EXPECT_LT(Eigen::AngleAxisd(e.linear()).angle(), 1e-5) << "frame " << k;
  }
  for (size_t j = 0; j < map.size(); ++j) {
    if (!points[map.ids[j]]) continue;
    // A landmark 40 m away is known to about a metre in depth: a few mm is that flat.
    EXPECT_LT((points[map.ids[j]]->estimate() - map.positions[j]).norm(), 5e-3) << j;
  }
}

}  // namespace
}  // namespace plugslam
