#pragma once
// The laser2d front-end (preprocessor + MultiTracker2D with the laser2d slices) over a CARMEN
// log, timed; shared by the intel integration test and the laser2d_bench tool.
#include <string>
#include <utility>
#include <vector>

#include "plugslam/eval/rpe.h"
#include "plugslam/trajectory.h"

namespace plugslam::laser2d::test {

/// How to run the front-end.
struct FrontendOptions {
  std::string association = "kdtree";  ///< kdtree | projective
  bool odometry = true;   ///< predict from the log's ODOM increments, else constant velocity
  double split_distance = 1.0;  ///< local map split distance [m]
  int repeat = 1;         ///< runs over the log (timing only; the last run is kept)
  std::string map_dir;    ///< when set, the occupancy map of the estimate is written there
  /// Parameter overrides "module.param" -> YAML value text, module one of preprocessor,
  /// slice, map, aligner (e.g. {"slice.max_distance", "0.3"}).
  std::vector<std::pair<std::string, std::string>> overrides;
};

/// What a run measured.
struct FrontendRun {
  size_t scans = 0;            ///< scans tracked (per run)
  double seconds = 0;          ///< wall time of the front-end alone, best run
  double scans_per_second = 0;  ///< scans / seconds
  size_t aligned = 0;          ///< frames whose alignment was valid
  size_t local_maps = 0;       ///< local maps created
  double mean_inlier_ratio = 0;
  size_t beams = 0;            ///< beams of the first scan
  Trajectory estimate;         ///< world poses, t = scan index
  Trajectory reference;        ///< the log's (GMapping-corrected) poses, t = scan index
};

/// Reads `log` (CARMEN, plain or gzip) and runs the front-end; throws InputError on a bad file.
FrontendRun runFrontend(const std::string& log, const FrontendOptions& options = {});

/// Relative error over `meters` of travel against the reference.
RpeResult relativeError(const FrontendRun& run, double meters);

}  // namespace plugslam::laser2d::test
