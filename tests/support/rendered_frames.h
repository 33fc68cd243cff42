#pragma once
// Frames of the 3D simulator as the camera tests need them (stereo and RGB-D): the raw entries
// a camera source would deliver, and the renderer's exact depth to check keypoint depth against.
// Header-only; include it from tests that link plugslam_sim_core.
#include <utility>

#include "plugslam/frame.h"
#include "plugslam/sensor_data.h"
#include "sim3d/renderer.h"
#include "sim3d/simulator.h"

namespace plugslam::testing {

/// The simulator's street (a block loop of buildings) seen by its stereo rig, seed 0.
inline sim::sim3d::Simulator3D streetStereo() {
  sim::sim3d::ScenarioOptions o;
  o.world = "street";
  o.rig = sim::sim3d::Rig::kStereo;
  o.seed = 0;
  return sim::sim3d::Simulator3D::fromOptions(o);
}

/// Frame k of `sim` with its raw entries: "left"/"right" for a stereo rig, "rgb"/"depth" for an
/// RGB-D one, "camera" (CameraInfo) and "ground_truth" (camera pose in the world) for both.
inline Frame renderedFrame(const sim::sim3d::Simulator3D& sim, size_t k) {
  sim::sim3d::Sim3DFrame f;
  sim.render(k, &f);
  Frame frame;
  frame.seq = k;
  frame.stamp = f.stamp;
  if (f.depth.width > 0) {
    frame.raw.set<Image>("rgb", std::move(f.left));
    frame.raw.set<DepthImage>("depth", std::move(f.depth));
  } else {
    frame.raw.set<Image>("left", std::move(f.left));
    frame.raw.set<Image>("right", std::move(f.right));
  }
  frame.raw.set<CameraInfo>("camera", sim.cameraInfo());
  frame.raw.set<Eigen::Isometry3d>("ground_truth", f.pose);
  return frame;
}

/// The noise-free depth the camera `cam` at `pose` (in the world) sees of the simulator's world.
inline sim::sim3d::RenderBuffers exactDepth(const sim::sim3d::Simulator3D& sim,
                                            const sim::sim3d::PinholeCamera& cam,
                                            const Eigen::Isometry3d& pose) {
  sim::sim3d::RenderBuffers b;
  sim::sim3d::RenderOptions ro;
  ro.shade = false;
  sim::sim3d::render(sim.world(), cam, pose, &b, nullptr, ro);
  return b;
}

}  // namespace plugslam::testing
