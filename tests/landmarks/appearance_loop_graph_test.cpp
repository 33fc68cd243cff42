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

// sdk.GraphSlam3D, deterministic, with the appearance detector and validator; `by_estimate`
// and `agreeing` as its join_by_estimate and join_agreeing.
std::shared_ptr<GraphSlam<Space3D>> appearanceGraph(bool by_estimate, int agreeing = 2) {
  auto graph =
      std::dynamic_pointer_cast<GraphSlam<Space3D>>(Registry::instance().create("sdk.GraphSlam3D"));
  if (!graph) return graph;
  graph->deterministic = true;
  graph->join_by_estimate = by_estimate;
  graph->join_agreeing = agreeing;
  auto detector = std::make_shared<AppearanceDetector>();
  detector->min_travel = 50.0;  // maps 15 m around share landmarks with their neighbours
  detector->configure();
  graph->loop_detectors.assign(detector);
  auto validator = std::make_shared<AppearanceValidator>();
  validator->configure();
  graph->validators.assign(validator);
  graph->configure();
  return graph;
}

TEST(AppearanceLoop, GraphSlam3DClosesASyntheticLoopAndRemovesTheDrift) {
  const World w = makeWorld();
  auto graph_ptr = appearanceGraph(true);
  ASSERT_TRUE(graph_ptr);
  GraphSlam<Space3D>& graph = *graph_ptr;

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

// Two robots map parts of the square from unknown starts (join_by_estimate false): the second's
// maps form their own component until appearance loops from two of its places agree on where it
// lies; then both are in one frame. A third robot in another building (other landmarks, but one
// place that looks exactly like one of the square's: a single loop validates) is never joined.
// Robot A maps 0..19 of the square from its start; robot B maps 12..31, its own frame at its first
// map; robot C the other building's maps 0..9, its own frame too, its map 4 a copy of A's map 5.
// With join_by_estimate false and `agreeing` places required; the maps and the final components.
struct ThreeRobots {
  std::vector<std::shared_ptr<LocalMap>> maps;
  std::vector<int64_t> components;
};
ThreeRobots driveThreeRobots(const World& w, const World& elsewhere, int agreeing) {
  auto graph_ptr = appearanceGraph(false, agreeing);
  GraphSlam<Space3D>& graph = *graph_ptr;
  std::mt19937 rng(5);
  ThreeRobots r;
  auto& maps = r.maps;
  const auto drive = [&](const World& world, size_t first, size_t last, size_t look_alike) {
    const auto start = static_cast<int64_t>(maps.size());
    for (size_t k = first; k <= last; ++k) {
      auto m = k == look_alike ? mapOf(w, 5, rng) : mapOf(world, k, rng);
      m->id = static_cast<int64_t>(maps.size());
      if (k > first) {
        m->previous = m->id - 1;
        m->relative = world.origins[k - 1].inverse() * world.origins[k];
        m->information = Eigen::Matrix<double, 6, 6>::Identity() * 1e4;
        m->origin = maps.back()->origin * m->relative;
      }
      maps.push_back(m);
      graph.mapStarted(m);
      if (m->id > start) graph.mapClosed(maps[static_cast<size_t>(m->id - 1)]);
    }
    graph.mapClosed(maps.back());
  };
  drive(w, 0, 19, 99);
  drive(w, 12, 31, 99);
  drive(elsewhere, 0, 9, 4);
  graph.finish();
  r.components = graphComponents(maps.size(), graph.edges());
  return r;
}

// Place recognition by appearance joins a robot started elsewhere once two of its places agree
// on where it lies; a third robot in another building is never joined although one of its places
// looks exactly like one of the square's (that single loop validates: trusted alone, it welds the
// buildings together).
TEST(AppearanceLoop, PlaceRecognitionJoinsARobotStartedElsewhere) {
  const World w = makeWorld();
  World elsewhere = makeWorld();
  std::mt19937 other_rng(77);
  for (auto& d : elsewhere.descriptors) d = testing::randomDescriptor(other_rng);
  const ThreeRobots r = driveThreeRobots(w, elsewhere, 2);
  for (size_t i = 20; i < 40; ++i) EXPECT_EQ(r.components[i], 0) << "B's map " << i;
  for (size_t i = 40; i < 50; ++i) EXPECT_EQ(r.components[i], 40) << "C's map " << i;
  // B in A's frame (A's first map is its origin): where the truth has it.
  double worst = 0;
  for (size_t i = 20; i < 40; ++i) {
    const Eigen::Isometry3d truth = w.origins[0].inverse() * w.origins[i - 8];
    worst = std::max(worst, (r.maps[i]->origin.translation() - truth.translation()).norm());
  }
  std::printf("robot B joined: worst map origin %.3f m from the truth\n", worst);
  EXPECT_LT(worst, 0.1);
  // The look-alike place alone: with one loop enough, C is welded to the square.
  const ThreeRobots trusting = driveThreeRobots(w, elsewhere, 1);
  EXPECT_EQ(trusting.components[40], 0) << "the look-alike loop did not validate: no test";
}

}  // namespace
}  // namespace plugslam
