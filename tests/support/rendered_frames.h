#pragma once
// Frames of the 3D simulator as the camera tests need them (stereo and RGB-D): the raw entries
// a camera source would deliver, and the renderer's exact depth to check keypoint depth against.
// Header-only; include it from tests that link plugslam_sim_core.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "plugslam/frame.h"
#include "plugslam/landmarks/feature_set.h"
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

/// |depth error| / sigma of every keypoint of `f` with depth, against the exact depth `truth`
/// at the keypoints' `raw_pixels` (those with no exact depth left out).
inline std::vector<double> normalizedErrors(const FeatureSet& f,
                                            const sim::sim3d::RenderBuffers& truth,
                                            const std::vector<Eigen::Vector2d>& raw_pixels) {
  std::vector<double> out;
  for (size_t i = 0; i < f.size(); ++i) {
    if (!f.hasDepth(i)) continue;
    const int u = static_cast<int>(std::lround(raw_pixels[i].x()));
    const int v = static_cast<int>(std::lround(raw_pixels[i].y()));
    const double z = truth.depth[static_cast<size_t>(v * truth.width + u)];
    if (!(z > 0)) continue;
    out.push_back(std::abs(f.points[i].z() - z) / std::sqrt(f.covariances[i](2, 2)));
  }
  return out;
}

/// What a camera preprocessor made of frame k of the simulator: its keypoints, how many have a
/// depth, and the normalizedErrors of that depth against the renderer's exact depth.
struct KeypointDepth {
  FeatureSet features;
  size_t with_depth = 0;  ///< keypoints that have a depth
  std::vector<double> errors;
};

/// Frame k of `sim` through the camera preprocessor `pre` (configured), its keypoints' depth
/// against the exact depth (camera without distortion: raw pixels = ideal); a failure and no
/// keypoints when `pre` rejects the frame.
template <class Preprocessor>
KeypointDepth keypointDepth(Preprocessor& pre, const sim::sim3d::Simulator3D& sim, size_t k) {
  Frame frame = renderedFrame(sim, k);
  KeypointDepth out;
  if (!pre.process(frame)) {
    ADD_FAILURE() << "frame " << k << " rejected";
    return out;
  }
  out.features = frame.measurement.get<FeatureSet>("features");
  for (size_t i = 0; i < out.features.size(); ++i) out.with_depth += out.features.hasDepth(i);
  const auto truth =
      exactDepth(sim, sim.camera(), frame.raw.get<Eigen::Isometry3d>("ground_truth"));
  out.errors = normalizedErrors(out.features, truth, out.features.pixels);
  return out;
}

/// The median of `v` (the upper one of an even count).
inline double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

/// The share of `v` below `bound`.
inline double fractionBelow(const std::vector<double>& v, double bound) {
  return static_cast<double>(
             std::count_if(v.begin(), v.end(), [&](double x) { return x < bound; })) /
         static_cast<double>(v.size());
}

}  // namespace plugslam::testing
