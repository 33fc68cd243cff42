#pragma once
// The viewer's hold on `plugslam shell --serve`: its services are the shell's own commands
// (pause, resume, step, save, do), and its parameters those of the loaded config: set like the
// shell's `set` while no run is in progress, and while one is, validated like `--set` and applied
// to the live module between frames, as `run --serve` does. Requests wait on the control's own
// thread, never on the server's.
#include <functional>
#include <memory>

#include "runner.h"
#include "shell/shell.h"
#include "view/job_thread.h"
#include "view/view_control.h"
#include "view/view_hub.h"
#include "view/view_stream.h"

namespace plugslam::runtime {

/// ViewControl of a shell, and the observer of its runs.
class ShellControl final : public ViewControl, public RunObserver {
 public:
  /// Controls `shell`, whose runs publish into `hub`; `out_dir` bounds save_session.
  ShellControl(ViewHub& hub, std::string out_dir);
  ~ShellControl() override;
  /// Binds the shell (created after this, with its options pointing here).
  void attach(Shell& shell);
  /// Refuses further calls, answers the waiting ones, stops the thread.
  void shutdown();
  /// For ShellOptions::on_state.
  void stateChanged(const std::string& state);

  // RunObserver of the shell's runs: each run's frames go to the viewer as a stream of its own.
  void frame(const Frame& frame, Pipeline& pipeline, uint64_t frames, int64_t total) override;
  void finished(const RunResult& result, Pipeline& pipeline) override;

  std::vector<foxglove::Service> services() override;
  void getParameters(std::vector<std::string> names, ParametersDone done) override;
  void setParameters(std::vector<foxglove::ParameterAssignment> assignments,
                     ParametersDone done) override;
  void call(const std::string& service, const std::string& request, CallDone done) override;

 private:
  // Queues a request for the control's thread; false (and `refuse` called) when stopped or busy.
  void enqueue(std::function<void()> job, std::function<void()> refuse);

  ViewHub& hub_;
  std::string out_dir_;
  Shell* shell_ = nullptr;
  std::unique_ptr<ViewStream> stream_;  // the current run's (guarded by the shell's frames lock)
  uint64_t runs_ = 0;
  JobThread jobs_;  // last: stops first, while the members its jobs use still exist
};

}  // namespace plugslam::runtime
