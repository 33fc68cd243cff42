#pragma once
// Runs a built pipeline over its source and writes run.json.
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "playback_clock.h"
#include "read_ahead.h"
#include "plugslam/errors.h"
#include "plugslam/statistics.h"
#include "plugslam/timings.h"
#include "plugslam/tracker.h"
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
  /// The failures by reason (run.json's keys, see AlignFailure), each reason once, in enum order.
  std::vector<std::pair<std::string, uint64_t>> tracking_failure_reasons;
  /// The tracker's counters as the run ended (run.json's other tracking_ keys).
  TrackerStats tracking;
  uint64_t module_errors = 0;       ///< frames a module failed on, skipped (on_module_error: skip)
  std::string error;                ///< the error that stopped the run, if one did
  GraphStats graph;                 ///< loops accepted/rejected, optimization time
  /// Each graph component's first map and number of maps, in order (one while every map is
  /// joined; a session or a tracker reset no loop joined adds one).
  std::vector<std::pair<int64_t, uint64_t>> graph_components;
  /// Localization from an unknown start: frames before it locked on (-1: it never did; 0: the
  /// start was known or it locked on at once).
  int64_t locked_on_after = 0;
  /// Against the source's ground truth, when it has one (SE2/SE3-aligned ATE, RPE over 1 m).
  std::optional<double> ate_rmse, ate_max, rpe_rmse;
  std::string rpe_unavailable;  ///< why rpe_rmse is empty when ate_rmse is set (a short run)
  /// Figures the modules report themselves (StatisticsSource), by module name.
  std::vector<std::pair<std::string, std::vector<Statistic>>> statistics;
};

class Execution;

/// Watches a run frame by frame (the viewer stream) and may hold it between two frames (a
/// viewer's pause and step, its parameter changes and actions, which run there).
class RunObserver {
 public:
  virtual ~RunObserver();
  /// After each processed frame, on the run's thread (timed as the module "viewer").
  virtual void frame(const Frame& frame, Pipeline& pipeline, uint64_t frames, int64_t total) = 0;
  /// Before each frame of runPipeline (not the shell's steps); may block while paused.
  virtual void betweenFrames(Execution& execution) { (void)execution; }
  /// Once the run is finished (final corrections applied), before run.json.
  virtual void finished(const RunResult& result, Pipeline& pipeline) {
    (void)result;
    (void)pipeline;
  }
};

/// Options of one run.
struct RunOptions {
  std::string out_dir;
  /// Called after each frame (progress display); may be empty. `loops` = loops accepted so far.
  std::function<void(uint64_t frame, int64_t total, double elapsed_s, uint64_t loops)> progress;
  /// Checked between frames: when it returns true the run stops ("interrupted"); may be empty.
  std::function<bool()> interrupted;
  /// Called once when `interrupted` stopped the run, before the run finishes: the final
  /// optimization of a large graph can take minutes, so a front-end saves what is built first.
  std::function<void()> on_interrupt;
  /// Called with false when the run's final work starts (the back-end's final loop passes and
  /// optimization, the sinks' outputs: seconds to minutes on a large graph, with no frames to
  /// count) and with true when it ends, also on an error; may be empty.
  std::function<void(bool done)> finishing;
  /// Called when an error stopped the run, after its outputs and run.json were written (so a
  /// front-end can save the session); may be empty. The error is rethrown afterwards.
  std::function<void()> stopped_by_error;
  /// Watches the run (the viewer stream); may be null. Outlives the run.
  RunObserver* observer = nullptr;
  /// Playback rate (--rate): 0 = as fast as possible; R > 0 = frames paced by their stamps at R
  /// times the data's own speed (1 = as recorded), e.g. to watch a log in the viewer.
  double rate = 0;
  /// Waits until a paced frame is due, instead of the clock (a test records the schedule); may be
  /// empty. runPipeline checks `interrupted` once more after it returns.
  std::function<void(PlaybackClock::Clock::time_point due)> wait_until;
};

/// One run driven frame by frame (the shell steps it; runPipeline loops it). Not thread-safe:
/// callers serialize step(), finish() and reads of the pipeline.
class Execution {
 public:
  /// Prepares the run: creates the output folder and starts the sinks.
  Execution(RunConfig& run, RunOptions options);
  /// Processes one frame; false (and nothing done) at the end of the data or max_frames. A
  /// module's ModuleError is thrown, or under `on_module_error: skip` (pipeline modules and
  /// sinks, not the source) warned about and the frame skipped. Never waits: callers that pace
  /// the run wait for nextDue() first.
  bool step();
  /// When the next frame is due at the playback rate (reads it from the source if not yet read;
  /// now when unpaced or at the end of the data). step() then processes that frame.
  PlaybackClock::Clock::time_point nextDue();
  /// Changes the playback rate (RunOptions::rate) from the next frame on.
  void setRate(double rate);
  /// Ends the run: pipeline finish, sinks end, scoring, run.json. Only once. `error`: what
  /// stopped the run, recorded in run.json.
  RunReport finish(const std::string& stopped_by = "", const std::string& error = "");
  /// Frames processed so far.
  uint64_t frames() const { return report_.frames; }
  /// Seconds since the run started.
  double elapsed() const;
  /// Frames this run will process: the source's count, bounded by max_frames; -1 if unknown.
  int64_t total() const { return total_; }
  /// True once the data (or max_frames) is exhausted.
  bool exhausted() const { return exhausted_; }
  /// True once finish() ran.
  bool finished() const { return finished_; }

 private:
  RunConfig& run_;
  RunOptions options_;
  RunReport report_;
  // Reads the next frame into pending_ (unless one waits there); false at the end.
  bool fetch();
  PlaybackClock clock_;
  std::unique_ptr<Frame> pending_;  // read from the source, not processed yet
  PlaybackClock::Clock::time_point due_{};
  double first_stamp_ = 0;
  // Under on_module_error: skip, one frame's module error (warned; counted).
  void skipped(uint64_t seq, const ModuleError& e);
  Timings io_timings_;
  int64_t total_ = -1;
  std::chrono::steady_clock::time_point start_;
  bool exhausted_ = false, finished_ = false;
  uint64_t frozen_frames_ = 0;  // frames tracked in frozen maps (localization)
  // Reads the source ahead (RunConfig::read_ahead); last, so it stops before the rest goes.
  std::unique_ptr<ReadAhead> reader_;
};

/// Runs source -> pipeline -> sinks to the end of the data (or max_frames, or until
/// options.interrupted says so), paced at options.rate; writes run.json. An error during the run
/// (bad input, a failing module) stops it cleanly: the run is finished (outputs, run.json with the
/// error), then options.stopped_by_error is called and the error rethrown.
RunReport runPipeline(RunConfig& run, const RunOptions& options);

/// "against 'REFERENCE': ATE ..., RPE(1 m) ..." (or why there is no RPE), one line; empty when
/// the run was not scored. `reference`: the pipeline's reference entry.
std::string scoreLine(const RunReport& report, const std::string& reference);

/// run.json's content.
std::string runReportJson(const RunReport& report);

/// "N loops closed", plus the restored session's loops kept when there are any.
std::string loopsClosedText(const GraphStats& graph);

}  // namespace plugslam::runtime
