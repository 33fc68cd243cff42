// plugslam validate CONFIG | run [CONFIG] -o OUTDIR
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <boost/filesystem.hpp>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>

#include "cli.h"
#include "commands/commands.h"
#include "config_builder.h"
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

void addRunCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand("run", "Run a pipeline and write its outputs");
  static std::string file;
  static std::string out_dir = "out";
  static std::vector<std::string> sets;
  static std::string session_dir;
  static bool localize = false;
  static std::vector<std::string> actions;
  static double checkpoint_every = 60.0;
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
  cmd->add_option("--checkpoint-every", checkpoint_every,
                  "save the session into OUTDIR/checkpoint every this many seconds of the run, "
                  "atomically, so even a killed run leaves a loadable session (0: never)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--do", actions,
                  "after the run, run a module action: MODULE.ACTION[:ARG,...] (repeatable)");
  addViewerOptions(*cmd, viewer_options);
  cmd->callback([&exit_code] {
    if (localize && session_dir.empty()) throw InputError("--localize needs --session DIR");
    std::optional<SessionManifest> manifest;
    if (!session_dir.empty()) manifest = readSessionManifest(session_dir);
    PluginManager plugins;
    ConfigDocument doc = !file.empty() ? loadConfigFile(file)
                         : manifest  ? loadConfigText(manifest->config_text, manifest->config_path)
                                     : loadConfigFile(defaultConfigPath());
    for (const auto& s : sets) applyOverride(doc, s);
    auto run = buildRun(doc, plugins);
    if (manifest) {
      // After buildRun: the config's plugins register the value types the scenes hold.
      SessionMaps maps = loadSessionMaps(*manifest);
      run->pipeline->restoreSession(maps.maps, maps.edges, localize);
      spdlog::info("session {}: {} local maps, {} edges ({})", session_dir, maps.maps.size(),
                   maps.edges.size(), localize ? "localization" : "mapping");
    }
    RunOptions options;
    options.out_dir = out_dir;
    const bool tty = ::isatty(STDERR_FILENO);
    std::string config_yaml = YAML::Dump(doc.root) + "\n";  // a viewer's settings update it
    Pipeline* pipeline = run->pipeline.get();
    options.progress = [tty, last = -1.0, last_checkpoint = 0.0, pipeline, &config_yaml](
                           uint64_t frame, int64_t total, double t, uint64_t loops) mutable {
      // Between frames the front-end is idle, so the pipeline's state can be saved as it is.
      if (checkpoint_every > 0 && t - last_checkpoint >= checkpoint_every) {
        last_checkpoint = t;
        writeCheckpoint((boost::filesystem::path(out_dir) / "checkpoint").string(), config_yaml,
                        *pipeline);
      }
      if (t - last < (tty ? 0.2 : 5.0)) return;
      last = t;
      double hz = t > 0 ? frame / t : 0;
      std::string pct = total > 0 ? fmt::format(" {:5.1f}%", 100.0 * frame / total) : "";
      std::string eta = total > 0 && hz > 0 ? fmt::format(" ETA {:.0f}s", (total - (int64_t)frame) / hz) : "";
      if (tty)
        std::fprintf(stderr, "\r  frame %llu%s  %.1f Hz%s  loops %llu   ", (unsigned long long)frame,
                     pct.c_str(), hz, eta.c_str(), (unsigned long long)loops);
      else
        spdlog::info("frame {}{} {:.1f} Hz{} loops {}", frame, pct, hz, eta, loops);
    };
    options.interrupted = [] { return g_interrupted.load(); };
    const std::string session_out = (boost::filesystem::path(out_dir) / "session").string();
    options.on_interrupt = [&] {
      // Saved before the final optimization and the outputs, which can take minutes on a large
      // graph: a second Ctrl-C (the default action again) then loses nothing built so far.
      SessionSummary s = writeCheckpoint(session_out, config_yaml, *run->pipeline);
      std::cerr << fmt::format(
          "\ninterrupted: session saved in {} ({} local maps); finishing the run (final "
          "optimization, outputs); Ctrl-C again quits now and keeps that session\n",
          session_out, s.maps);
    };
    options.stopped_by_error = [&] {
      // The maps built before the error are kept: the same session an interrupted run saves.
      const std::string dir = (boost::filesystem::path(out_dir) / "session").string();
      SessionSummary s = saveSession(dir, config_yaml, *run->pipeline);
      std::cout << fmt::format("run stopped by an error: outputs written in {}, session saved in "
                               "{} ({} local maps); continue with: plugslam run --session {}\n",
                               out_dir, dir, s.maps, dir);
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
          [] { return g_interrupted.load(); }, &config_yaml);
      options.observer = control.get();
      viewer.serve(control.get());
    }
    spdlog::info("running {} -> {}", doc.file, out_dir);
    RunReport report;
    {
      InterruptGuard guard;
      report = runPipeline(*run, options);
    }
    if (control) control->shutdown();
    viewer.stop();
    if (tty) std::fprintf(stderr, "\n");
    std::cout << fmt::format(
        "{} frames in {:.3f} s ({:.1f} Hz; pipeline alone {:.1f} Hz); {}; outputs in {}\n",
        report.frames, report.wall_s, report.hz, report.pipeline_hz,
        loopsClosedText(report.graph), out_dir);
    if (report.ate_rmse)
      std::cout << fmt::format("against '{}': ATE rmse {:.4f} m (max {:.4f} m), RPE(1 m) rmse {:.4f} m\n",
                               run->pipeline->reference(), *report.ate_rmse, *report.ate_max,
                               report.rpe_rmse.value_or(NAN));
    if (report.stopped_by == "interrupted") {
      // Again, now with the final optimization; atomically, so a kill mid-save keeps the first.
      SessionSummary s = writeCheckpoint(session_out, config_yaml, *run->pipeline);
      std::cout << fmt::format("interrupted at frame {}: session saved in {} ({} local maps); "
                               "continue with: plugslam run --session {}\n",
                               report.frames, session_out, s.maps, session_out);
      exit_code = kInterrupted;
      return;
    }
    for (const auto& a : actions) {
      const auto colon = a.find(':');
      std::vector<std::string> args;
      if (colon != std::string::npos) {
        std::stringstream list(a.substr(colon + 1));
        std::string item;
        while (std::getline(list, item, ',')) args.push_back(item);
      }
      std::cout << a.substr(0, colon) << ": " << invokeAction(*run, a.substr(0, colon), args)
                << "\n";
    }
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
