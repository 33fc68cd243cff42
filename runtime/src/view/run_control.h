#pragma once
// The viewer's hold on `plugslam run --serve`: parameter changes, pause, step, session saves and
// module actions queue up and run on the run's own thread between two frames, so nothing touches
// the pipeline while it processes one; while paused, the run's thread waits for them. A setting is
// first validated like `--set` (the whole config rebuilt on a copy, off the run's thread), then
// applied to the live module.
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>

#include "plugin_manager.h"
#include "run_config.h"
#include "runner.h"
#include "view/job_thread.h"
#include "view/view_control.h"
#include "view/view_stream.h"

namespace plugslam::runtime {

/// ViewControl and RunObserver of one `plugslam run`.
class RunControl final : public ViewControl, public RunObserver {
 public:
  /// Writes a session into `dir`; returns what was saved, as one line.
  using SaveSession = std::function<std::string(const std::string& dir)>;

  /// Controls `run` (built from `doc` with `plugins`), whose outputs go to `out_dir`; frames go to
  /// `stream`. `interrupted` (may be empty) ends a pause when it turns true (Ctrl-C).
  /// `config_yaml` (may be null) is kept equal to configYaml() on the run's thread.
  RunControl(RunConfig& run, ConfigDocument& doc, PluginManager& plugins, std::string out_dir,
             ViewStream& stream, SaveSession save_session, std::function<bool()> interrupted,
             std::string* config_yaml = nullptr, bool start_paused = false);
  ~RunControl() override;
  RunControl(const RunControl&) = delete;
  RunControl& operator=(const RunControl&) = delete;

  /// Refuses further calls and answers the waiting ones; call before the server goes.
  void shutdown();
  /// The config as YAML, with the parameters set so far (what a session saves).
  std::string configYaml() const;

  std::vector<foxglove::Service> services() override;
  void getParameters(std::vector<std::string> names, ParametersDone done) override;
  void setParameters(std::vector<foxglove::ParameterAssignment> assignments,
                     ParametersDone done) override;
  void call(const std::string& service, const std::string& request, CallDone done) override;

  void frame(const Frame& frame, Pipeline& pipeline, uint64_t frames, int64_t total) override;
  void betweenFrames(Execution& execution) override;
  void finished(const RunResult& result, Pipeline& pipeline) override;

 private:
  using Command = std::function<void(Execution*)>;  // null execution: the run has ended
  // Queues `command` for the run's thread; false when the run has ended.
  bool enqueue(Command command);
  void runQueued(std::unique_lock<std::mutex>& lock, Execution* execution);

  RunConfig& run_;
  ConfigDocument& doc_;
  PluginManager& plugins_;
  std::string out_dir_;
  ViewStream& stream_;
  SaveSession save_session_;
  std::function<bool()> interrupted_;
  std::string* config_yaml_;
  std::vector<foxglove::Service> services_;

  std::mutex after_end_mutex_;  // serializes the commands run once the run has ended
  mutable std::mutex mutex_;    // guards everything below, and doc_
  std::condition_variable cv_;
  std::deque<Command> queue_;
  bool ended_ = false;
  bool paused_ = false;
  long long budget_ = 0;   // frames left to step while paused
  CallDone step_done_;     // the step call in progress
  uint64_t frames_ = 0;    // frames processed so far

  // Settings (and config editor requests) waiting for validation, on their own thread; last, so
  // that it stops while the members its jobs use still exist.
  JobThread validator_;
};

}  // namespace plugslam::runtime
