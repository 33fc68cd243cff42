#include "landmark_cue.h"

#include <cmath>
#include <limits>

#include "plugslam/registry.h"

namespace plugslam::testing {

bool LandmarkSlice::bind(const Frame& frame, const PropertyContainer& scene,
                         const AlignContext<Space2D>&) {
  measured_ = frame.measurement.find<Landmarks>(entry());
  mapped_ = scene.find<Landmarks>(entry());
  return measured_ && mapped_;
}

void LandmarkSlice::linearize(const Eigen::Isometry2d& t, NormalEquations<Space2D>& eq) const {
  const double w = 1.0 / (sigma() * sigma());
  const Eigen::Matrix2d r = t.linear();
  for (size_t i = 0; i < measured_->size(); ++i) {
    const Eigen::Vector2d& p = (*measured_)[i];
    if (!p.allFinite()) continue;
    ++eq.candidates;
    if (i >= mapped_->size() || !(*mapped_)[i].allFinite()) continue;
    const Eigen::Vector2d e = t * p - (*mapped_)[i];
    Eigen::Matrix<double, 2, 3> j;
    j.leftCols<2>() = r;
    j.col(2) = r * Eigen::Vector2d(-p.y(), p.x());
    eq.H += w * j.transpose() * j;
    eq.b += w * j.transpose() * e;
    eq.chi2 += w * e.squaredNorm();
    ++eq.factors;
    ++eq.inliers;
  }
}

void LandmarkMapSlice::merge(const Frame& frame, PropertyContainer& scene,
                             const Eigen::Isometry2d& t) {
  const Landmarks* m = frame.measurement.find<Landmarks>(entry());
  if (!m) return;
  Landmarks* map = scene.find<Landmarks>(entry());
  if (!map) map = &scene.set<Landmarks>(entry(), {});
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
