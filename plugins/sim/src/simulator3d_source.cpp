#include "simulator3d_source.h"

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {

Simulator3DSource::Simulator3DSource() = default;
Simulator3DSource::~Simulator3DSource() = default;

void Simulator3DSource::configure() {
  sim3d::ScenarioOptions o;
  o.world = world();
  o.rig = camera() == "stereo" ? sim3d::Rig::kStereo : sim3d::Rig::kRgbd;
  o.trajectory_file = trajectory();
  o.trajectory_format = trajectory_format();
  o.kitti_times = kitti_times();
  o.anchor = anchor();
  o.rate = rate();
  o.duration = duration();
  o.speed = speed();
  o.seed = static_cast<uint64_t>(seed());
  o.image_noise.enabled = image_noise();
  o.image_noise.sigma = image_sigma();
  o.image_noise.gain_sigma = exposure_sigma();
  o.depth_noise.enabled = depth_noise();
  o.depth_noise.max_range = depth_max_range();
  if (!kitti_times().empty() && trajectory().empty())
    throw ParamError("kitti_times", "only used with a trajectory file");
  for (const char* fixed : {"left", "right", "rgb", "depth", "camera"})
    if (ground_truth() == fixed)
      throw ParamError("ground_truth", std::string("clashes with the image entry '") + fixed + "'");
  sim_ = std::make_unique<sim3d::Simulator3D>(sim3d::Simulator3D::fromOptions(o));
  next_ = 0;
}

const sim3d::Simulator3D& Simulator3DSource::simulator() const {
  if (!sim_) throw InputError("sim.Simulator3D: configure() was not called");
  return *sim_;
}

std::vector<ProvidedEntry> Simulator3DSource::provides() const {
  if (!sim_) return {};  // the rig is known once configured
  std::vector<ProvidedEntry> out;
  if (sim_->rig() == sim3d::Rig::kStereo)
    out = {{"left", typeid(Image)}, {"right", typeid(Image)}};
  else
    out = {{"rgb", typeid(Image)}, {"depth", typeid(DepthImage)}};
  out.push_back({"camera", typeid(CameraInfo)});
  out.push_back({ground_truth(), typeid(Eigen::Isometry3d)});
  return out;
}

int64_t Simulator3DSource::sizeHint() const {
  return sim_ ? static_cast<int64_t>(sim_->frameCount()) : -1;
}

bool Simulator3DSource::next(Frame& frame) {
  if (!sim_) configure();
  if (next_ >= sim_->frameCount()) return false;
  sim3d::Sim3DFrame f;
  sim_->render(next_++, &f);
  frame.stamp = f.stamp;
  if (sim_->rig() == sim3d::Rig::kStereo) {
    frame.raw.set<Image>("left", std::move(f.left));
    frame.raw.set<Image>("right", std::move(f.right));
  } else {
    frame.raw.set<Image>("rgb", std::move(f.left));
    frame.raw.set<DepthImage>("depth", std::move(f.depth));
  }
  frame.raw.set<CameraInfo>("camera", sim_->cameraInfo());
  frame.raw.set<Eigen::Isometry3d>(ground_truth(), f.pose);
  return true;
}

}  // namespace sim
}  // namespace plugslam
