#pragma once
// How well reference poses explain their own depth images, and what the depth alone says each
// frame-to-frame motion is (rgbd_depth_check, the ICL rows of scripts/bench/visual.sh and the
// ICL test): every pair of frames at most `max_gap` apart is aligned densely from the
// reference's relative pose; a consecutive pair that shares no surface is measured through the
// frame that shares the most with both.
#include <optional>
#include <string>
#include <vector>

#include "depth_alignment.h"
#include "plugslam/source.h"

namespace plugslam {
namespace rgbd {

/// One frame of a check: its stamp, reference pose (world <- camera) and depth surface.
struct DepthCheckFrame {
  double stamp = 0;                        ///< [s]
  SE3 reference = SE3::Identity();         ///< the dataset's pose of the camera
  DepthSurface surface;                    ///< its depth, in the colour camera's pinhole
};

/// A pair of frames aligned by their depth.
struct DepthCheckPair {
  int i = 0, j = 0;                 ///< frames, i < j
  DepthAlignmentResult alignment;   ///< i <- j, from the reference's relative pose
  double overlap = 0;               ///< pairs / points at the end
  bool shares_surface = false;      ///< ok and overlap >= kMinDepthOverlap
  SE3 reference_off = SE3::Identity();  ///< reference^-1 * depth's relative pose
};

/// A consecutive pair's motion by the depth, when measurable.
struct DepthCheckStep {
  int i = 0, j = 0;                   ///< j = i + 1
  std::optional<SE3> depth;           ///< i <- j by the depth; empty: no surface links them
  int via = -1;                       ///< the frame it was measured through (-1: directly)
  SE3 reference = SE3::Identity();    ///< i <- j by the reference
};

/// A tenth of the moving points must land on the other image's surface: less is a sliver of
/// wall, too little to fix six degrees of freedom.
constexpr double kMinDepthOverlap = 0.10;

/// The pairs at most `max_gap` apart and the consecutive steps of `frames`.
struct DepthCheck {
  std::vector<DepthCheckPair> pairs;  ///< every pair tried
  std::vector<DepthCheckStep> steps;  ///< frames i, i + 1
  int cycles = 0;                     ///< closed triangles of pairs sharing surface
  double cycle_max_m = 0;             ///< their worst closure, translation [m]
  double cycle_max_rad = 0;           ///< and rotation [rad]
};

/// Every frame of `source` (configured) with its depth (raw entry `depth`, registered to the
/// colour camera of raw `camera`) and ground truth (raw `ground_truth`); InputError naming the
/// frame and entry when one is missing.
std::vector<DepthCheckFrame> readDepthCheckFrames(Source& source, const std::string& depth,
                                                  const std::string& camera,
                                                  const std::string& ground_truth);

/// Runs the check.
DepthCheck checkDepth(const std::vector<DepthCheckFrame>& frames, int max_gap,
                      const DepthAlignmentOptions& options = {});

}  // namespace rgbd
}  // namespace plugslam
