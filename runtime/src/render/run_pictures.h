#pragma once
// `plugslam render`: pictures of what a run wrote. The map with the estimated trajectory, the
// reference (aligned onto the estimate) and the loop closures; plots of ATE per pose over time
// and distance, and of RPE over distance.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "plugslam/eval/ate.h"
#include "plugslam/trajectory.h"
#include "render/figure.h"

namespace plugslam::runtime::render {

/// What `render` found in a run's folder.
struct RunData {
  std::string dir;
  Trajectory estimate;                  ///< trajectory.tum (or the file given)
  std::optional<Trajectory> reference;  ///< reference.tum or ground_truth.tum, when present
  std::string reference_path;
  int dimension = 2;                       ///< 2 for planar runs (graph of SE2 or a flat path)
  std::vector<Eigen::Vector2d> nodes;      ///< graph vertices (local maps), top view
  std::vector<Eigen::Vector2d> loop_ends;  ///< loop-closure edges, two points each
  std::optional<GreyRaster> map;           ///< map.yaml + its image, when present
  /// A merged run (`plugslam merge`, merge.json): each joined session's trajectory, by name.
  std::vector<std::pair<std::string, Trajectory>> sessions;
  std::vector<Eigen::Vector2d> link_ends;  ///< links across sessions, two points each
};

/// Options of the pictures.
struct RenderOptions {
  int width = 1000;                    ///< figure width [px]
  std::optional<Alignment> alignment;  ///< reference onto estimate; default SE2 / SE3
  double rpe_delta = 1.0;              ///< RPE segment length [m]
  std::string estimate_file;           ///< default: DIR/trajectory.tum
  std::string reference_file;          ///< default: DIR/reference.tum or ground_truth.tum
  std::vector<std::string> formats{"png", "svg"};  ///< file extensions written: png, svg, pdf
};

/// Reads a run's folder; throws InputError naming the file when something is unreadable, and
/// when there is no trajectory at all.
RunData loadRun(const std::string& dir, const RenderOptions& options = {});

/// The map (or a plain x-y plot) with the trajectories and loop closures. Series names
/// (css_class): "reference", "estimate", "loops", "nodes", "start".
Figure mapFigure(const RunData& run, const RenderOptions& options = {});
/// ATE over time and distance, RPE over distance; throws InputError without a reference.
Figure errorFigure(const RunData& run, const RenderOptions& options = {});

/// Loads `dir`, writes render_map.EXT and, with a reference, render_errors.EXT into out_dir
/// (created if needed), one file per format of options.formats; returns the files written.
std::vector<std::string> renderRun(const std::string& dir, const std::string& out_dir,
                                   const RenderOptions& options = {});

}  // namespace plugslam::runtime::render
