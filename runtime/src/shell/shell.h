#pragma once
// The interactive shell (`plugslam shell`): load a config, run it on a worker thread, pause,
// step, inspect and change parameters, trigger module actions, hot-swap module types and
// reload rebuilt plugins, save and load sessions. Commands never throw: an error prints one line
// and leaves the state as it was. Reference: docs/shell.md.
#include <atomic>
#include <functional>
#include <condition_variable>
#include <iosfwd>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "config_builder.h"
#include "plugin_manager.h"
#include "run_config.h"
#include "runner.h"
#include "session/session.h"

namespace plugslam::runtime {

/// Settings of one shell.
struct ShellOptions {
  std::string out_dir = "out";  ///< where runs write their outputs and run.json
  bool echo = false;            ///< print each command before its output (scripts)
  double rate = 0;              ///< playback rate of runs (--rate, `rate R`; RunOptions::rate)
  /// Watches every run (the viewer stream); may be null.
  RunObserver* observer = nullptr;
  /// Told when a run starts ("running"), pauses ("paused") or resumes, between frames; may be
  /// empty.
  std::function<void(const std::string& state)> on_state;
};

class ShellControl;

/// The shell's state and command interpreter; `execute` runs one command line.
class Shell {
 public:
  /// A shell printing to `out`.
  Shell(std::ostream& out, ShellOptions options);
  /// Stops a run in progress (its outputs are still written).
  ~Shell();
  Shell(const Shell&) = delete;
  Shell& operator=(const Shell&) = delete;

  /// Executes one command line; false once the shell should exit (quit). Thread-safe: commands
  /// run one at a time.
  bool execute(const std::string& line);
  /// Executes one command line with its output returned instead of printed; `ok` is false when
  /// it failed.
  std::string capture(const std::string& line, bool& ok);
  /// Commands that failed so far.
  int errors() const { return errors_; }
  /// The command names, for completion.
  static const std::vector<std::string>& commandNames();

 private:
  friend class ShellControl;  // the viewer's access to the tree, between frames
  enum class State { kIdle, kRunning, kPaused, kFinished };
  bool executeLocked(const std::string& line);
  void tellState(const char* state) const {
    if (options_.on_state) options_.on_state(state);
  }
  using Args = std::vector<std::string>;

  void dispatch(const std::string& cmd, const Args& args, const std::string& rest);
  void cmdLoad(const Args& a);
  void cmdValidate();
  void cmdRun();
  void cmdPause();
  void cmdResume();
  void cmdStep(const Args& a);
  void cmdStop();
  void cmdWait();
  void cmdStatus();
  void cmdSet(const std::string& rest);
  void cmdGet(const Args& a);
  void cmdList(const Args& a);
  void cmdDo(const Args& a);
  void cmdPlugins();
  void cmdReload(const Args& a);
  void cmdSwap(const Args& a);
  void cmdSave(const Args& a);
  void cmdLoadSession(const Args& a);
  void cmdHelp();
  void cmdRate(const Args& a);

  // Builds a module tree from `doc` (plus the loaded session); throws on any error.
  std::shared_ptr<RunConfig> build(const ConfigDocument& doc);
  // Replaces the document and tree once `doc` has built.
  void commit(ConfigDocument doc);
  RunConfig& tree();
  bool active() const;  // an execution exists and has not finished
  void requireIdle(const std::string& what) const;
  void startExecution(int64_t budget);
  void workerLoop();
  void joinWorker();
  void reportWorkerError();
  // Every lock taken by the command thread: the worker lets go of the mutex between frames
  // while someone waits (std::mutex is not fair, so a plain lock could wait for the whole run).
  std::unique_lock<std::mutex> lockBetweenFrames() const;
  void printReport(const RunReport& r);

  std::ostream* out_;  // the terminal, or a capture's buffer
  std::recursive_mutex command_mutex_;  // one command at a time (terminal, viewer)
  ShellOptions options_;
  PluginManager plugins_;
  std::optional<ConfigDocument> doc_;
  std::shared_ptr<RunConfig> run_;
  bool tree_used_ = false;  // the tree has processed frames: rebuild before the next run

  // The loaded session, re-applied to every tree built from the document.
  struct LoadedSession {
    SessionManifest manifest;
    SessionMaps maps;
    bool localize = false;
  };
  std::optional<LoadedSession> session_;

  // Run on the worker thread; everything below is guarded by mutex_.
  std::unique_ptr<Execution> exec_;
  std::thread worker_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  State state_ = State::kIdle;
  int64_t budget_ = -1;  // frames left before pausing (-1: no limit)
  bool stop_requested_ = false;
  std::string worker_error_;
  std::optional<RunReport> report_;
  mutable std::atomic<int> waiting_{0};  // commands waiting for the worker to let go between frames

  int errors_ = 0;
};

/// Runs the shell: readline with history when `interactive`, else lines from `in`. Returns 0,
/// or 1 when a non-interactive script had failing commands.
int runShellLoop(Shell& shell, std::istream& in, bool interactive);

}  // namespace plugslam::runtime
