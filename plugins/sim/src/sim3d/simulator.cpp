#include "sim3d/simulator.h"

#include "plugslam/errors.h"
#include "sim3d/trajectory.h"

namespace plugslam {
namespace sim {
namespace sim3d {

Simulator3D::Simulator3D(std::shared_ptr<const World> world, Rig rig, const PinholeCamera& camera,
                         double baseline, Trajectory trajectory, const DepthNoise& depth_noise,
                         const ImageNoise& image_noise, uint64_t seed)
    : world_(std::move(world)),
      rig_(rig),
      camera_(camera),
      baseline_(baseline),
      trajectory_(std::move(trajectory)),
      depth_noise_(depth_noise),
      image_noise_(image_noise),
      seed_(seed) {
  if (!world_) throw InputError("sim3d simulator: expected a world");
  camera_.validate();
  if (rig_ == Rig::kStereo && !(baseline_ > 0.0))
    throw InputError("sim3d simulator: a stereo rig needs a positive baseline");
  if (trajectory_.empty()) throw InputError("sim3d simulator: the trajectory is empty");
  depth_noise_.validate();
  image_noise_.validate();
}

std::shared_ptr<const World> makeWorld(const std::string& name, uint64_t seed,
                                       const RoadPath& road) {
  if (name == "livingroom") return std::make_shared<const World>(World::livingRoom(seed));
  if (name == "street")
    return std::make_shared<const World>(
        World::street(road.empty() ? blockLoop(160.0, 100.0, 12.0, 2.0) : road, {}, seed));
  throw InputError("sim3d: unknown world '" + name + "'; expected livingroom or street");
}

Simulator3D Simulator3D::fromOptions(const ScenarioOptions& o) {
  if (o.world != "livingroom" && o.world != "street")
    throw InputError("sim3d: unknown world '" + o.world + "'; expected livingroom or street");
  if (!(o.rate >= 0.0)) throw InputError("sim3d: rate must be >= 0");
  const bool stereo = o.rig == Rig::kStereo;
  const double rate = o.rate > 0.0 ? o.rate : (stereo ? 10.0 : 30.0);
  const double camera_height = kCameraHeight;
  Trajectory trajectory;
  RoadPath road;
  if (o.trajectory_file.empty()) {
    if (o.world == "livingroom") {
      trajectory = livingRoomLoop(o.duration > 0.0 ? o.duration : 30.0, rate);
    } else {
      road = blockLoop(160.0, 100.0, 12.0, 2.0);
      trajectory = driveAlong(road, camera_height, o.speed, rate, o.acceleration);
    }
  } else {
    trajectory = readTrajectory(o.trajectory_file, parseTrajectoryFormat(o.trajectory_format),
                                o.kitti_times);
    if (trajectory.size() < 2)
      throw InputError("sim3d: trajectory '" + o.trajectory_file + "' has fewer than two poses");
    if (o.rate > 0.0) trajectory = resampleTrajectory(trajectory, o.rate);
    if (o.anchor)
      trajectory =
          anchorTrajectory(trajectory, o.world == "street" ? streetStart() : livingRoomStart());
    if (o.world == "street") road = roadUnder(trajectory, camera_height, 3.0);
  }
  if (o.pan != 0.0) trajectory = panTrajectory(trajectory, o.pan, o.pan_period);
  const PinholeCamera camera = stereo ? PinholeCamera::kitti() : PinholeCamera::vga();
  return Simulator3D(makeWorld(o.world, o.seed, road), o.rig, camera, 0.54, std::move(trajectory),
                     o.depth_noise, o.image_noise, o.seed);
}

CameraInfo Simulator3D::cameraInfo() const {
  CameraInfo c = camera_.info();
  c.baseline = rig_ == Rig::kStereo ? baseline_ : 0.0;
  return c;
}

void Simulator3D::render(size_t index, Sim3DFrame* frame) const {
  if (index >= trajectory_.size())
    throw InputError("sim3d simulator: frame " + std::to_string(index) + " out of range (" +
                     std::to_string(trajectory_.size()) + " frames)");
  const StampedPose& sp = trajectory_[index];
  frame->index = index;
  frame->stamp = sp.t;
  frame->pose = sp.pose;
  const double gain = exposureGain(image_noise_, seed_, sp.t);
  RenderBuffers buffers;
  if (rig_ == Rig::kStereo) {
    frame->left.channels = 1;
    frame->right.channels = 1;
    sim3d::render(*world_, camera_, sp.pose, &buffers, &frame->left);
    Eigen::Isometry3d right = sp.pose;
    right.translation() += sp.pose.linear().col(0) * baseline_;
    sim3d::render(*world_, camera_, right, &buffers, &frame->right);
    applyImageNoise(image_noise_, seed_, index, 0, gain, &frame->left);
    applyImageNoise(image_noise_, seed_, index, 1, gain, &frame->right);
    frame->depth = DepthImage();
  } else {
    frame->left.channels = 3;
    sim3d::render(*world_, camera_, sp.pose, &buffers, &frame->left);
    applyImageNoise(image_noise_, seed_, index, 0, gain, &frame->left);
    makeDepthImage(buffers, depth_noise_, seed_, index, &frame->depth);
    frame->right = Image();
  }
  frame->left.stamp = frame->right.stamp = frame->depth.stamp = sp.t;
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
