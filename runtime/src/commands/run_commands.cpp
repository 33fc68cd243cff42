// plugslam validate CONFIG | run [CONFIG] -o OUTDIR
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <boost/filesystem.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli.h"
#include "commands/commands.h"
#include "config_builder.h"
#include "plugslam/errors.h"
#include "run_config.h"
#include "runner.h"

namespace plugslam::runtime {

namespace {

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

void addRunCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand("run", "Run a pipeline and write its outputs");
  static std::string file;
  static std::string out_dir = "out";
  static std::vector<std::string> sets;
  cmd->add_option("CONFIG", file, "pipeline YAML file (default: the built-in demo config)");
  cmd->add_option("-o,--output", out_dir, "output folder (created if missing)")->capture_default_str();
  cmd->add_option("--set", sets, "override a parameter: PATH=VALUE (repeatable)");
  cmd->callback([&exit_code] {
    if (file.empty()) file = defaultConfigPath();
    PluginManager plugins;
    auto doc = loadWithOverrides(file, sets);
    auto run = buildRun(doc, plugins);
    RunOptions options;
    options.out_dir = out_dir;
    const bool tty = ::isatty(STDERR_FILENO);
    options.progress = [tty, last = -1.0](uint64_t frame, int64_t total, double t) mutable {
      if (t - last < (tty ? 0.2 : 5.0)) return;
      last = t;
      double hz = t > 0 ? frame / t : 0;
      std::string pct = total > 0 ? fmt::format(" {:5.1f}%", 100.0 * frame / total) : "";
      std::string eta = total > 0 && hz > 0 ? fmt::format(" ETA {:.0f}s", (total - (int64_t)frame) / hz) : "";
      if (tty)
        std::fprintf(stderr, "\r  frame %llu%s  %.1f Hz%s   ", (unsigned long long)frame,
                     pct.c_str(), hz, eta.c_str());
      else
        spdlog::info("frame {}{} {:.1f} Hz{}", frame, pct, hz, eta);
    };
    spdlog::info("running {} -> {}", file, out_dir);
    RunReport report = runPipeline(*run, options);
    if (tty) std::fprintf(stderr, "\n");
    std::cout << fmt::format("{} frames in {:.3f} s ({:.1f} Hz; pipeline alone {:.1f} Hz); outputs in {}\n",
                             report.frames, report.wall_s, report.hz, report.pipeline_hz, out_dir);
    if (report.ate_rmse)
      std::cout << fmt::format("against '{}': ATE rmse {:.4f} m (max {:.4f} m), RPE(1 m) rmse {:.4f} m\n",
                               run->pipeline->reference(), *report.ate_rmse, *report.ate_max,
                               report.rpe_rmse.value_or(NAN));
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
