#include "simulator_mixed_source.h"

#include <set>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {

SimulatorMixedSource::SimulatorMixedSource() = default;
SimulatorMixedSource::~SimulatorMixedSource() = default;

void SimulatorMixedSource::configure() {
  std::set<std::string> names{"rgb", "depth", "camera"};
  for (const auto* p : {&laser, &odometry, &ground_truth}) {
    if ((*p)().empty()) throw ParamError(p->name(), "needs an entry name");
    if (!names.insert((*p)()).second)
      throw ParamError(p->name(), "'" + (*p)() + "' clashes with another raw entry");
  }
  sim3d::MixedOptions o;
  o.path_length = path_length();
  o.rate = rate();
  o.laser.name = laser();
  o.laser.mount = Eigen::Vector3d(0.2, 0.0, 0.0);
  o.laser.beams = beams();
  o.laser.fov = fov();
  o.laser.max_range = max_range();
  o.laser.range_sigma = range_noise();
  o.laser.dropout = dropout();
  o.laser_height = laser_height();
  o.odometry_noise = odometry_noise();
  o.image_noise.enabled = image_noise();
  o.depth_noise.enabled = depth_noise();
  o.seed = static_cast<uint64_t>(seed());
  sim_ = std::make_unique<sim3d::MixedSimulator>(o);
}

std::vector<ProvidedEntry> SimulatorMixedSource::provides() const {
  return {{laser(), typeid(LaserScan)},       {"rgb", typeid(Image)},
          {"depth", typeid(DepthImage)},      {"camera", typeid(CameraInfo)},
          {odometry(), typeid(Odometry2D)},   {ground_truth(), typeid(Eigen::Isometry3d)}};
}

int64_t SimulatorMixedSource::sizeHint() const {
  return sim_ ? static_cast<int64_t>(sim_->frameCount()) : -1;
}

bool SimulatorMixedSource::next(Frame& frame) {
  if (!sim_) configure();
  sim3d::MixedFrame f;
  if (!sim_->step(&f)) return false;
  frame.stamp = f.stamp;
  frame.raw.set<LaserScan>(laser(), std::move(f.scan));
  frame.raw.set<Image>("rgb", std::move(f.rgb));
  frame.raw.set<DepthImage>("depth", std::move(f.depth));
  frame.raw.set<CameraInfo>("camera", sim_->cameraInfo());
  frame.raw.set<Odometry2D>(odometry(), {f.stamp, f.odometry});
  frame.raw.set<Eigen::Isometry3d>(ground_truth(), f.base);
  return true;
}

}  // namespace sim
}  // namespace plugslam
