// plugslam shell [CONFIG] [--script FILE] [-o OUTDIR]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "cli.h"
#include "commands/commands.h"
#include "playback_clock.h"
#include "plugslam/errors.h"
#include "shell/shell.h"
#include "view/shell_control.h"
#include "view/viewer.h"

namespace plugslam::runtime {

void addShellCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "shell", "Interactive shell: run, pause, step, set, actions, hot swap, sessions");
  static std::string config;
  static std::string script;
  static std::string out_dir = "out";
  static double rate = 0.0;
  static ViewerOptions viewer_options;
  cmd->add_option("CONFIG", config, "config to load first");
  cmd->add_option("--script", script, "read commands from this file instead of stdin");
  cmd->add_option("-o,--output", out_dir, "output folder of runs")->capture_default_str();
  cmd->add_option("--rate", rate, kPlaybackRateHelp)->capture_default_str()->check(CLI::NonNegativeNumber);
  addViewerOptions(*cmd, viewer_options);
  cmd->callback([&exit_code] {
    const bool interactive = script.empty() && ::isatty(STDIN_FILENO);
    ShellOptions options;
    options.out_dir = out_dir;
    options.rate = rate;
    options.echo = !interactive;
    // The viewer (--serve, --record) watches every run and drives the shell's own commands.
    Viewer viewer(viewer_options);
    std::unique_ptr<ShellControl> control;
    if (viewer.active()) {
      control = std::make_unique<ShellControl>(viewer.hub(), out_dir);
      options.observer = control.get();
      options.on_state = [c = control.get()](const std::string& s) { c->stateChanged(s); };
    }
    Shell shell(std::cout, options);
    // The control's thread uses the shell: it stops before the shell goes, also on an error.
    struct StopFirst {
      ShellControl* control;
      ~StopFirst() {
        if (control) control->shutdown();
      }
    } stop_first{control.get()};
    if (control) control->attach(shell);
    if (!config.empty()) shell.execute("load " + config);
    viewer.serve(control.get());
    if (!script.empty()) {
      std::ifstream in(script);
      if (!in) throw InputError("cannot open shell script '" + script + "'");
      exit_code = runShellLoop(shell, in, false);
    } else {
      exit_code = runShellLoop(shell, std::cin, interactive);
    }
    if (control) control->shutdown();
    viewer.stop();
  });
}

}  // namespace plugslam::runtime
