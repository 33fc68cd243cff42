// 3D loop closing through appearance: sdk.GraphSlam3D with sdk.AppearanceDetector and
// sdk.AppearanceValidator on a synthetic drive (local maps of described 3D landmarks around a
// climbing square, odometry that turns too far at every map) closes the loop and removes the
// drift, although the drifted estimate puts the return far from the start.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "plugslam/graph_slam.h"
#include "plugslam/landmarks/appearance_detector.h"
#include "plugslam/landmarks/appearance_validator.h"
#include "plugslam/landmarks/landmark_map.h"
#include "plugslam/registry.h"
#include "random_descriptors.h"

namespace plugslam {
namespace {

struct World {
  std::vector<Eigen::Vector3d> points;
  std::vector<testing::Descriptor> descriptors;
  std::vector<Eigen::Isometry3d> origins;  // true map origins; the last is back at the first
};

// Maps every 4 m around a 40 x 40 m square climbing 0.25 m a map (back down at the end), among
// 2500 landmarks with their own descriptors in a 70 x 70 x 8 m slab.
World makeWorld() {
  World w;
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> xy(-35, 35), z(-2, 6);
  for (int i = 0; i < 2500; ++i) {
    w.points.emplace_back(xy(rng), xy(rng), z(rng));
    w.descriptors.push_back(testing::randomDescriptor(rng));
  }
  const Eigen::Vector2d corners[4] = {{-20, -20}, {20, -20}, {20, 20}, {-20, 20}};
  for (int k = 0; k <= 40; ++k) {
    const int side = std::min(k / 10, 3), step = k - 10 * side;
    const Eigen::Vector2d a = corners[side], b = corners[(side + 1) % 4];
    const Eigen::Vector2d p = k == 40 ? corners[0] : Eigen::Vector2d(a + (b - a) * (step / 10.0));
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translation() = Eigen::Vector3d(p.x(), p.y(), k == 40 ? 0.0 : 0.25 * k);
    const double heading = k == 40 ? 0.0 : std::atan2((b - a).y(), (b - a).x());
    t.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    w.origins.push_back(t);
  }
  return w;
}

// The landmarks within 15 m of origin k, in the map's frame, with 2 cm noise and 15 of 256
// descriptor bits flipped (another viewpoint).
std::shared_ptr<LocalMap> mapOf(const World& w, size_t k, std::mt19937& rng) {
  auto m = std::make_shared<LocalMap>();
  m->id = static_cast<int64_t>(k);
  m->dimension = 3;
  LandmarkMap& lm = m->scene.emplace<LandmarkMap>("landmarks");
  std::normal_distribution<double> noise(0, 0.02);
  const Eigen::Isometry3d to_map = w.origins[k].inverse();
  for (size_t i = 0; i < w.points.size(); ++i) {
    const Eigen::Vector3d p = to_map * w.points[i];
    if (p.head<2>().norm() > 15) continue;
    const testing::Descriptor d = testing::perturbed(w.descriptors[i], 15, rng);
    lm.push(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)),
            Eigen::Matrix3d::Identity() * 0.02 * 0.02, i, d.data(), 0, 0);
    lm.observations.back() = 3;
  }
  return m;
}

TEST(AppearanceLoop, GraphSlam3DClosesASyntheticLoopAndRemovesTheDrift) {
  const World w = makeWorld();
  auto graph_ptr =
      std::dynamic_pointer_cast<GraphSlam<Space3D>>(Registry::instance().create("sdk.GraphSlam3D"));
  ASSERT_TRUE(graph_ptr);
  GraphSlam<Space3D>& graph = *graph_ptr;
  graph.deterministic = true;
  auto detector = std::make_shared<AppearanceDetector>();
  detector->min_travel = 50.0;  // maps 15 m around share landmarks with their neighbours
  detector->configure();
  graph.loop_detectors.assign(detector);
  auto validator = std::make_shared<AppearanceValidator>();
  validator->configure();
  graph.validators.assign(validator);
  graph.configure();

  std::mt19937 rng(4);
  std::vector<std::shared_ptr<LocalMap>> maps;
  Eigen::Isometry3d estimate = w.origins[0];
  // Odometry turns 0.01 rad too far (yaw) and climbs 1 cm too much at every map.
  Eigen::Isometry3d bias = Eigen::Isometry3d::Identity();
  bias.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  bias.translation() = Eigen::Vector3d(0, 0, 0.01);
  for (size_t k = 0; k < w.origins.size(); ++k) {
    auto m = mapOf(w, k, rng);
    if (k > 0) {
      const Eigen::Isometry3d rel = w.origins[k - 1].inverse() * w.origins[k] * bias;
      estimate = estimate * rel;
      m->previous = static_cast<int64_t>(k - 1);
      m->relative = rel;
      Eigen::Matrix<double, 6, 1> sigma;
      sigma << 0.02, 0.02, 0.02, 0.01, 0.01, 0.01;  // the bias is one sigma a map
      m->information = sigma.array().square().inverse().matrix().asDiagonal();
    }
    m->origin = estimate;
    maps.push_back(m);
    graph.mapStarted(m);
    if (k > 0) graph.mapClosed(maps[k - 1]);
  }
  graph.mapClosed(maps.back());
  graph.finish();

  const Eigen::Vector3d end_truth = w.origins.back().translation();
  const double before = (estimate.translation() - end_truth).norm();
  const double after = (maps.back()->origin.translation() - end_truth).norm();
  const GraphStats s = graph.stats();
  std::printf("closing error: %.3f m dead reckoning, %.3f m after; loops %llu accepted, %llu "
              "rejected\n",
              before, after, static_cast<unsigned long long>(s.loops_accepted),
              static_cast<unsigned long long>(s.loops_rejected));
  // The drifted return lies metres from the start: a proximity search would not look there.
  EXPECT_GT(before, 5.0);
  // Expected, NOT YET MEASURED (see the printout of the first run): loop edges from ~300 inliers
  // of 2 cm noise fix the return to millimetres; 0.1 m fails when no loop closes or a loop joins
  // the wrong maps (dead reckoning ends metres off).
  EXPECT_LT(after, 0.1);
  EXPECT_GE(s.loops_accepted, 1u);
  double worst = 0;
  for (const GraphEdge& e : graph.edges()) {
    if (!e.loop) continue;
    const Eigen::Isometry3d truth = w.origins[static_cast<size_t>(e.from)].inverse() *
                                    w.origins[static_cast<size_t>(e.to)];
    worst = std::max(worst, (truth.inverse() * e.relative).translation().norm());
  }
  EXPECT_LT(worst, 0.1) << "every accepted loop is a true one";
}

}  // namespace
}  // namespace plugslam
