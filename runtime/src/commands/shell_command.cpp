// plugslam shell [CONFIG] [--script FILE] [-o OUTDIR]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "cli.h"
#include "commands/commands.h"
#include "plugslam/errors.h"
#include "shell/shell.h"

namespace plugslam::runtime {

void addShellCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "shell", "Interactive shell: run, pause, step, set/get, actions, hot swap, sessions");
  static std::string config;
  static std::string script;
  static std::string out_dir = "out";
  cmd->add_option("CONFIG", config, "config to load first");
  cmd->add_option("--script", script, "read commands from this file instead of stdin");
  cmd->add_option("-o,--output", out_dir, "output folder of runs")->capture_default_str();
  cmd->callback([&exit_code] {
    const bool interactive = script.empty() && ::isatty(STDIN_FILENO);
    ShellOptions options;
    options.out_dir = out_dir;
    options.echo = !interactive;
    Shell shell(std::cout, options);
    if (!config.empty()) shell.execute("load " + config);
    if (!script.empty()) {
      std::ifstream in(script);
      if (!in) throw InputError("cannot open shell script '" + script + "'");
      exit_code = runShellLoop(shell, in, false);
    } else {
      exit_code = runShellLoop(shell, std::cin, interactive);
    }
  });
}

}  // namespace plugslam::runtime
