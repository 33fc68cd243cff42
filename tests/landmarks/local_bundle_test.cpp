// Local bundle adjustment: landmarks placed from one noisy stereo observation each, and frames
// whose poses were tracked with an error, settle on what all of the observations say.
#include "plugslam/landmarks/local_bundle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "plugslam/geometry.h"

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

TEST(LocalBundle, RefinesLandmarksAndTheFramesBetweenTheFixedOnes) {
  std::mt19937 rng(3);
  const Scene s = scene(rng);
  const PinholeCamera c = camera();
  const double sigma_px = 0.5, sigma_d = 0.3;  // pixels, disparity pixels
  std::normal_distribution<double> npx(0, sigma_px), nd(0, sigma_d);
  LandmarkMap map;
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
      f.observations.push_back(
          BundleObservation{i, Eigen::Vector3d(u, v, q),
                            Eigen::Vector3d(1 / (sigma_px * sigma_px), 1 / (sigma_px * sigma_px),
                                            1 / (sigma_q * sigma_q))});
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
  // The frames between the first and the last were tracked 10-20 cm and a few mrad off.
  for (size_t k = 1; k + 1 < frames.size(); ++k) {
    Vector6d off;
    off << 0.1, -0.05, 0.15, 0.003, -0.004, 0.002;
    frames[k].pose = frames[k].pose * se3(off);
  }
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

}  // namespace
}  // namespace plugslam
