#include "simulator3d_source.h"

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"
#include "sim3d/odometry.h"
#include "sim3d/trajectory.h"

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
  o.acceleration = acceleration();
  o.pan = pan() * M_PI / 180.0;
  o.pan_period = pan_period();
  if (pan() != 0.0 && !odometry().empty())
    throw ParamError("pan",
                     "a panned camera turns on the vehicle: its wheel odometry would not follow "
                     "the camera (set pan: 0 or odometry: '')");
  for (int k : drop_frames())
    if (k < 0) throw ParamError("drop_frames", "frame indices must be >= 0");
  o.seed = static_cast<uint64_t>(seed());
  o.image_noise.enabled = image_noise();
  o.image_noise.sigma = image_sigma();
  o.image_noise.gain_sigma = exposure_sigma();
  o.depth_noise.enabled = depth_noise();
  o.depth_noise.max_range = depth_max_range();
  if (!kitti_times().empty() && trajectory().empty())
    throw ParamError("kitti_times", "only used with a trajectory file");
  for (const char* fixed : {"left", "right", "rgb", "depth", "camera"}) {
    if (ground_truth() == fixed)
      throw ParamError("ground_truth", std::string("clashes with the image entry '") + fixed + "'");
    if (odometry() == fixed)
      throw ParamError("odometry", std::string("clashes with the image entry '") + fixed + "'");
  }
  if (odometry() == ground_truth()) throw ParamError("odometry", "must differ from ground_truth");
  sim_ = std::make_unique<sim3d::Simulator3D>(sim3d::Simulator3D::fromOptions(o));
  odometry_.clear();
  if (!odometry().empty()) {
    // Odometry integrates over the whole drive, so it is computed once here (it costs nothing
    // next to rendering) and frame k stays the same whatever order frames are asked in.
    sim3d::WheelOdometryOptions w;
    w.noise = w.noise.scaled(odometry_noise());
    w.wheel_base = wheel_base();
    w.camera_height = sim3d::kCameraHeight;
    w.seed = o.seed;
    odometry_ = sim3d::wheelOdometry(sim_->trajectory(), w);
  }
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
  if (!odometry().empty()) out.push_back({odometry(), typeid(Odometry2D)});
  return out;
}

int64_t Simulator3DSource::sizeHint() const {
  return sim_ ? static_cast<int64_t>(sim_->frameCount()) : -1;
}

bool Simulator3DSource::next(Frame& frame) {
  if (!sim_) configure();
  const std::vector<int>& dropped = drop_frames();
  while (next_ < sim_->frameCount() &&
         std::find(dropped.begin(), dropped.end(), static_cast<int>(next_)) != dropped.end())
    ++next_;
  if (next_ >= sim_->frameCount()) return false;
  sim3d::Sim3DFrame f;
  if (!odometry_.empty())
    frame.raw.set<Odometry2D>(odometry(), {sim_->trajectory()[next_].t, odometry_[next_]});
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
