// plugslam validate CONFIG | run [CONFIG] -o OUTDIR
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <boost/filesystem.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "cli.h"
#include "commands/commands.h"
#include "config_builder.h"
#include "console/status_line.h"
#include "playback_clock.h"
#include "plugslam/errors.h"
#include "run_config.h"
#include "runner.h"
#include "session/session.h"
#include "shell/module_paths.h"
#include "view/run_control.h"
#include "view/viewer.h"

namespace plugslam::runtime {

namespace {

// Set by SIGINT; the runner checks it between frames.
std::atomic<bool> g_interrupted{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the SIGINT flag must be lock-free");

extern "C" void onInterrupt(int) { g_interrupted.store(true); }

// Ctrl-C during a run: the first one asks the run to stop and save, a second one kills
// (SA_RESETHAND restores the default action).
class InterruptGuard {
 public:
  InterruptGuard() {
    g_interrupted = false;
    struct sigaction sa {};
    sa.sa_handler = onInterrupt;
    sa.sa_flags = SA_RESETHAND;
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGINT, &sa, &previous_);
  }
  ~InterruptGuard() { ::sigaction(SIGINT, &previous_, nullptr); }

 private:
  struct sigaction previous_ {};
};

ConfigDocument loadWithOverrides(const std::string& file, const std::vector<std::string>& sets) {
  ConfigDocument doc = loadConfigFile(file);
  for (const auto& s : sets) applyOverride(doc, s);
  return doc;
}

}  // namespace

void addValidateCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand("validate", "Check a config: plugins, types, keys, values");
  static std::string file;
  static std::vector<std::string> sets;
  cmd->add_option("CONFIG", file, "pipeline YAML file")->required();
  cmd->add_option("--set", sets, "override a parameter: PATH=VALUE (repeatable)");
  cmd->callback([&exit_code] {
    PluginManager plugins;
    auto doc = loadWithOverrides(file, sets);
    auto run = buildRun(doc, plugins);
    std::cout << file << ": OK (" << countModules(*run) - 1 << " modules, "
              << plugins.loaded().size() << " plugins)\n";
    exit_code = kOk;
  });
}

namespace {

// Saves a session into `dir` as a whole: written beside it first, then moved into place, so a
// kill at any moment leaves either the previous checkpoint or the new one (or, between the two
// renames, the previous one as dir.old), never a half-written session.
SessionSummary writeCheckpoint(const std::string& dir, const std::string& config_yaml,
                               Pipeline& pipeline) {
  namespace fs = boost::filesystem;
  const fs::path target(dir), fresh(dir + ".new"), old(dir + ".old");
  boost::system::error_code ec;
  fs::remove_all(fresh, ec);
  const SessionSummary summary = saveSession(fresh.string(), config_yaml, pipeline);
  fs::remove_all(old, ec);
  if (fs::exists(target)) fs::rename(target, old);
  fs::rename(fresh, target);
  fs::remove_all(old, ec);
  spdlog::debug("checkpoint written to {}", dir);
  return summary;
}

}  // namespace

namespace {

// One --do: "MODULE.ACTION[:ARG,...]".
struct ActionCall {
  std::string target;
  std::vector<std::string> args;
};

ActionCall parseAction(const std::string& text) {
  ActionCall call;
  const auto colon = text.find(':');
  call.target = text.substr(0, colon);
  if (colon != std::string::npos) {
    std::stringstream list(text.substr(colon + 1));
    for (std::string item; std::getline(list, item, ',');) call.args.push_back(item);
  }
  return call;
}

// The progress line of a run: frame, share of the frames this run will process, rate, ETA and
// loops, on the terminal's status line; every few seconds a log line when stderr is no terminal.
std::string progressText(uint64_t frame, int64_t total, double t, uint64_t loops) {
  const double hz = t > 0 ? frame / t : 0;
  std::string text = fmt::format("  frame {}", frame);
  if (total > 0) text += fmt::format("/{} {:5.1f}%", total, 100.0 * frame / total);
  text += fmt::format("  {:.1f} Hz", hz);
  if (total > 0 && hz > 0)
    text += fmt::format("  ETA {:.0f} s", std::max<double>(0, total - (int64_t)frame) / hz);
  return text + fmt::format("  loops {}", loops);
}

// While the run's final work goes on (final loop passes, final optimization, outputs: no frames
// to count), the elapsed time on the status line, or a log line every ten seconds off a terminal.
class FinishingTicker {
 public:
  void operator()(bool done) {
    if (!done) {
      start_ = std::chrono::steady_clock::now();
      if (StatusLine::console().terminal())
        StatusLine::console().show(text());
      else
        spdlog::info("finishing the run: final loop passes, final optimization, outputs");
      stop_ = false;
      thread_ = std::thread([this] { tick(); });
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
    StatusLine::console().clear();
    spdlog::debug("finished in {:.1f} s", elapsed());
  }
  ~FinishingTicker() {
    if (thread_.joinable()) (*this)(true);
  }

 private:
  double elapsed() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  void tick() {
    StatusLine& line = StatusLine::console();
    const auto period = std::chrono::milliseconds(line.terminal() ? 200 : 10000);
    std::unique_lock<std::mutex> lock(mutex_);
    while (!cv_.wait_for(lock, period, [this] { return stop_; })) {
      if (line.terminal())
        line.show(text());
      else
        spdlog::info("{}", text().substr(2));
    }
  }
  std::string text() const {
    return fmt::format("  finishing: final loop passes, optimization, outputs  {:.1f} s",
                       elapsed());
  }
  std::chrono::steady_clock::time_point start_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
};

// What `--session DIR` does with a saved session, said where a session is saved: it is no resume.
std::string sessionUse(const std::string& dir) {
  return fmt::format(
      "`plugslam run CONFIG --session {}` adds a new run's maps to it (multi-session mapping, "
      "the config's source from its first frame), `--localize` tracks in it without mapping",
      dir);
}

}  // namespace

void addRunCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand("run", "Run a pipeline and write its outputs");
  static std::string file;
  static std::string out_dir = "out";
  static std::vector<std::string> sets;
  static std::string session_dir;
  static bool localize = false;
  static std::vector<std::string> actions;
  static double checkpoint_every = 60.0;
  static double rate = 0.0;
  static ViewerOptions viewer_options;
  cmd->add_option("CONFIG", file,
                  "pipeline YAML file (default: the session's config with --session, else the "
                  "built-in demo config)");
  cmd->add_option("-o,--output", out_dir, "output folder (created if missing)")->capture_default_str();
  cmd->add_option("--set", sets, "override a parameter: PATH=VALUE (repeatable)");
  cmd->add_option("--session", session_dir,
                  "restore a saved session first: new maps extend it (multi-session mapping)");
  cmd->add_flag("--localize", localize,
                "with --session: track against the saved maps, frozen; no new maps or edges");
  static bool anywhere = false;
  cmd->add_flag("--start-anywhere", anywhere,
                "with --session: the run may start anywhere; only place recognition joins its "
                "maps to the saved ones, and --localize tracks in them once it has (else the run "
                "is assumed to start where the session did)");
  cmd->add_option("--checkpoint-every", checkpoint_every,
                  "save the session into OUTDIR/checkpoint every this many seconds of the run, "
                  "atomically, so even a killed run leaves a loadable session (0: never); removed "
                  "when the run ends and writes OUTDIR/session")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--rate", rate, kPlaybackRateHelp)->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--do", actions,
                  "after the run, run a module action: MODULE.ACTION[:ARG,...] (repeatable; "
                  "checked before the first frame)");
  addViewerOptions(*cmd, viewer_options, /*run_options=*/true);
  cmd->callback([&exit_code] {
    if (localize && session_dir.empty()) throw InputError("--localize needs --session DIR");
    if (anywhere && session_dir.empty()) throw InputError("--start-anywhere needs --session DIR");
    std::optional<SessionManifest> manifest;
    if (!session_dir.empty()) manifest = readSessionManifest(session_dir);
    PluginManager plugins;
    ConfigDocument doc = !file.empty() ? loadConfigFile(file)
                         : manifest  ? loadConfigText(manifest->config_text, manifest->config_path)
                                     : loadConfigFile(defaultConfigPath());
    for (const auto& s : sets) applyOverride(doc, s);
    if (anywhere) applyOverride(doc, "pipeline.graph.join_by_estimate=false");
    auto run = buildRun(doc, plugins);
    // A typo in an action fails now, not after a run of minutes.
    std::vector<ActionCall> calls;
    for (const auto& a : actions) {
      calls.push_back(parseAction(a));
      try {
        checkAction(*run, calls.back().target);
      } catch (const InputError& e) {
        throw InputError("--do " + a + ": " + e.what());
      }
    }
    if (manifest) {
      // After buildRun: the config's plugins register the value types the scenes hold.
      SessionMaps maps = loadSessionMaps(*manifest);
      run->pipeline->restoreSession(maps.maps, maps.edges, localize, !anywhere);
      spdlog::info("session {}: {} local maps, {} edges ({})", session_dir, maps.maps.size(),
                   maps.edges.size(), localize ? "localization" : "mapping");
    }
    RunOptions options;
    options.out_dir = out_dir;
    StatusLine& status = StatusLine::console();
    options.rate = rate;
    std::string config_yaml = resolvedYaml(doc);  // a viewer's settings update it
    Pipeline* pipeline = run->pipeline.get();
    const std::string checkpoint_dir = (boost::filesystem::path(out_dir) / "checkpoint").string();
    options.progress = [&status, last = -1.0, last_checkpoint = 0.0, pipeline, &config_yaml,
                        &checkpoint_dir](uint64_t frame, int64_t total, double t,
                                         uint64_t loops) mutable {
      // Between frames the front-end is idle, so the pipeline's state can be saved as it is.
      if (checkpoint_every > 0 && t - last_checkpoint >= checkpoint_every) {
        last_checkpoint = t;
        writeCheckpoint(checkpoint_dir, config_yaml, *pipeline);
      }
      if (t - last < (status.terminal() ? 0.2 : 5.0)) return;
      last = t;
      const std::string text = progressText(frame, total, t, loops);
      if (status.terminal())
        status.show(text);
      else
        spdlog::info("{}", text.substr(2));
    };
    FinishingTicker ticker;
    options.finishing = [&ticker](bool done) { ticker(done); };
    options.interrupted = [] { return g_interrupted.load(); };
    const std::string session_out = (boost::filesystem::path(out_dir) / "session").string();
    options.on_interrupt = [&] {
      // Saved before the final optimization and the outputs, which can take minutes on a large
      // graph: a second Ctrl-C (the default action again) then loses nothing built so far.
      SessionSummary s = writeCheckpoint(session_out, config_yaml, *run->pipeline);
      status.print(fmt::format(
          "\ninterrupted: session saved in {} ({} local maps); finishing the run (final "
          "optimization, outputs); Ctrl-C again quits now and keeps that session\n",
          session_out, s.maps));
    };
    options.stopped_by_error = [&] {
      // The maps built before the error are kept: the same session an interrupted run saves.
      SessionSummary s = saveSession(session_out, config_yaml, *run->pipeline);
      std::cout << fmt::format(
          "run stopped by an error: outputs written in {}, session saved in {} ({} local maps "
          "from the frames before the error); {}\n",
          out_dir, session_out, s.maps, sessionUse(session_out));
    };
    // The viewer (--serve, --record): it watches the run and queues its requests between frames.
    Viewer viewer(viewer_options);
    std::unique_ptr<RunControl> control;
    if (viewer.active()) {
      control = std::make_unique<RunControl>(
          *run, doc, plugins, out_dir, viewer.stream(),
          [&](const std::string& dir) {
            SessionSummary s = writeCheckpoint(dir, control->configYaml(), *run->pipeline);
            return fmt::format("saved session {}: {} local maps, {} edges", dir, s.maps, s.edges);
          },
          [] { return g_interrupted.load(); }, &config_yaml, viewer_options.paused);
      options.observer = control.get();
      viewer.serve(control.get());
    }
    spdlog::info("running {} -> {}", doc.file, out_dir);
    RunReport report;
    {
      InterruptGuard guard;
      report = runPipeline(*run, options);
    }
    // Viewers get the end of the run (its last map and graph) before the server closes.
    if (report.stopped_by != "interrupted" && !viewer_options.keep_serving) viewer.drain();
    if (viewer.server() && viewer_options.keep_serving && report.stopped_by != "interrupted") {
      std::cerr << "run finished; still serving " << viewer.server()->url()
                << " (Ctrl-C to quit)" << std::endl;
      InterruptGuard guard;
      while (!g_interrupted.load()) ::usleep(100000);
    }
    if (control) control->shutdown();
    viewer.stop();
    status.clear();
    const bool tracker = static_cast<bool>(run->pipeline->tracker);
    std::string summary =
        fmt::format("{} frames in {:.3f} s ({:.1f} Hz", report.frames, report.wall_s, report.hz);
    if (tracker) summary += fmt::format("; pipeline alone {:.1f} Hz", report.pipeline_hz);
    summary += ")";
    if (run->pipeline->graph)
      summary += "; " + loopsClosedText(report.graph);
    if (!tracker) summary += "; the pipeline has no tracker, so no pose was estimated";
    std::cout << summary << "; outputs in " << out_dir << "\n";
    std::cout << scoreLine(report, run->pipeline->reference());
    if (report.stopped_by == "interrupted") {
      // Again, now with the final optimization; atomically, so a kill mid-save keeps the first.
      SessionSummary s = writeCheckpoint(session_out, config_yaml, *run->pipeline);
      std::cout << fmt::format(
          "interrupted at frame {}: session saved in {} ({} local maps). It is not a point to "
          "resume from: {}\n",
          report.frames, session_out, s.maps, sessionUse(session_out));
      exit_code = kInterrupted;
      return;
    }
    if (tracker) {
      // Every run leaves its final session (the checkpoint was only a mid-run snapshot).
      SessionSummary s = writeCheckpoint(session_out, config_yaml, *run->pipeline);
      boost::system::error_code ec;
      boost::filesystem::remove_all(checkpoint_dir, ec);
      std::cout << fmt::format("session saved in {} ({} local maps)\n", session_out, s.maps);
    }
    for (const auto& call : calls)
      std::cout << call.target << ": " << invokeAction(*run, call.target, call.args) << "\n";
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
