#include "landmark_cue.h"

#include <cmath>
#include <limits>
#include <random>

#include "plugslam/registry.h"
#include "plugslam/splitter.h"

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

std::shared_ptr<MultiTracker<Space2D>> landmarkTracker(double split_distance) {
  registerLandmarkCue();
  auto tracker = std::dynamic_pointer_cast<MultiTracker<Space2D>>(
      Registry::instance().create("sdk.MultiTracker2D"));
  tracker->aligner.assign(Registry::instance().create("sdk.MultiAligner2D"));
  tracker->aligner->slices.assign(Registry::instance().create("lmtest.LandmarkSlice"));
  tracker->slices.assign(Registry::instance().create("lmtest.LandmarkMapSlice"));
  auto splitter = Registry::instance().create("sdk.DistanceSplitter");
  dynamic_cast<DistanceSplitter&>(*splitter).distance = split_distance;
  tracker->splitter.assign(splitter);
  tracker->configure();
  return tracker;
}

std::unique_ptr<Pipeline> trackingOnly(std::shared_ptr<Tracker> tracker) {
  auto pipeline = std::make_unique<Pipeline>();
  pipeline->tracker.assign(std::move(tracker));
  pipeline->configure();
  return pipeline;
}

Frame sequenceFrame(uint64_t seq) {
  Frame f;
  f.seq = seq;
  f.stamp = 0.1 * static_cast<double>(seq);
  return f;
}

}  // namespace plugslam::testing
