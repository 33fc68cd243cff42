#include "landmark_cue.h"

#include <cmath>
#include <limits>
#include <random>

#include "plugslam/registry.h"

namespace plugslam::testing {

Landmarks jitteredGrid(double step, double extent, unsigned seed) {
  Landmarks w;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  for (double x = -extent; x <= extent; x += step)
    for (double y = -extent; y <= extent; y += step)
      w.emplace_back(x + jitter(rng), y + jitter(rng));
  return w;
}

void LandmarkSliceBase::linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const {
  const double w = information();
  const Landmarks& measured = *measurement;
  const Landmarks& mapped = *scene;
  for (size_t i = 0; i < measured.size(); ++i) {
    const Eigen::Vector2d& p = measured[i];
    if (!p.allFinite()) continue;
    ++eq.candidates;
    if (i >= mapped.size() || !mapped[i].allFinite()) continue;
    eq.add(PointToPoint2D{p, mapped[i]}, t, w);
  }
}

void LandmarkMapSlice::integrate(const MergeContext<Space2D>& context) {
  const Eigen::Isometry2d& t = context.pose;
  const Landmarks* m = measurement.get();
  Landmarks* map = &scene.getOrInsert();
  if (map->size() < m->size())
    map->resize(m->size(), Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (size_t i = 0; i < m->size(); ++i)
    if ((*m)[i].allFinite() && !(*map)[i].allFinite()) (*map)[i] = t * (*m)[i];
}

void registerLandmarkCue() {
  static bool done = [] {
    Registrar r(Registry::instance(), "lmtest", nullptr);
    r.add<LandmarkSlice>("LandmarkSlice", "test landmark aligner slice");
    r.add<LandmarkMapSlice>("LandmarkMapSlice", "test landmark tracker slice");
    return true;
  }();
  (void)done;
}

Landmarks observe(const Landmarks& world, const Eigen::Isometry2d& pose, double range) {
  Landmarks out(world.size(),
                Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
  for (size_t i = 0; i < world.size(); ++i)
    if ((world[i] - pose.translation()).norm() <= range) out[i] = pose.inverse() * world[i];
  return out;
}

}  // namespace plugslam::testing
