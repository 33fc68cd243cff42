#pragma once
// Runs a built pipeline over its source and writes run.json.
#include <functional>
#include <optional>
#include <string>

#include "plugslam/timings.h"
#include "run_config.h"

namespace plugslam::runtime {

/// What a run did, as written to run.json.
struct RunReport {
  uint64_t frames = 0;
  double wall_s = 0;
  double hz = 0;
  double pipeline_s = 0;   ///< time inside the pipeline (not the source or the sinks)
  double pipeline_hz = 0;  ///< frames / pipeline_s: the SLAM system's own rate
  std::vector<TimingEntry> modules;
  std::string stopped_by;  ///< "end of data", "max_frames", ...
  uint64_t tracked = 0;    ///< frames with a pose estimate
  uint64_t local_maps = 0;
  uint64_t tracking_failures = 0;
  GraphStats graph;  ///< loops accepted/rejected, optimization time
  /// Against the source's ground truth, when it has one (SE2/SE3-aligned ATE, RPE over 1 m).
  std::optional<double> ate_rmse, ate_max, rpe_rmse;
};

/// Options of one run.
struct RunOptions {
  std::string out_dir;
  /// Called after each frame (progress display); may be empty.
  std::function<void(uint64_t frame, int64_t total, double elapsed_s)> progress;
};

/// Runs source -> pipeline -> sinks to the end of the data (or max_frames); writes run.json.
RunReport runPipeline(RunConfig& run, const RunOptions& options);

/// run.json's content.
std::string runReportJson(const RunReport& report);

/// Writes `content` to `path` atomically (temp file in the same folder, then rename).
void writeTextFileAtomic(const std::string& path, const std::string& content);

}  // namespace plugslam::runtime
