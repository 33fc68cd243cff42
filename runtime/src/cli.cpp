#include "cli.h"

#include <spdlog/sinks/basic_file_sink.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/filesystem.hpp>
#include <iostream>
#include <sstream>

#include "build_paths.h"
#include "commands/commands.h"
#include "console/status_line.h"
#include "plugslam/errors.h"
#include "plugslam/version.h"

namespace plugslam::runtime {

std::string defaultConfigPath() {
  namespace fs = boost::filesystem;
  // The built-in default is a shipped config, named once, here.
  const char* name = "sim2d_double_laser.yaml";
  fs::path exe = boost::dll::program_location();
  for (const fs::path& dir : {exe.parent_path().parent_path() / "share" / "plugslam" / "configs",
                              fs::path(build_paths::installDataDir()) / "configs",
                              fs::path(build_paths::sourceDir()) / "configs"}) {
    if (fs::exists(dir / name)) return (dir / name).string();
  }
  throw InputError(std::string("no config given and the default config (configs/") + name +
                   ") is not installed");
}

int runCli(int argc, char** argv) {
  CLI::App app{"plugslam: plug-and-play multi-sensor graph SLAM.\n"
               "Pipelines are YAML files; sensors, sources and outputs come from plugins.\n"
               "With no command, runs the built-in default pipeline (the simulated office)\n"
               "into out/, as `plugslam run` does."};
  app.require_subcommand(0, 1);
  // Global options (-v, -q, --log-file) may also follow the subcommand.
  app.fallthrough();
  app.set_version_flag("--version", std::string("plugslam ") + PLUGSLAM_VERSION_STRING +
                                        " (plugin ABI " + std::to_string(PLUGSLAM_ABI_MAJOR) +
                                        "." + std::to_string(PLUGSLAM_ABI_MINOR) + ")");
  int verbose = 0;
  bool quiet = false;
  std::string log_file;
  app.add_flag("-v,--verbose", verbose, "more log output (-vv for trace)");
  app.add_flag("-q,--quiet", quiet, "only errors");
  app.add_option("--log-file", log_file, "also write the log to this file");
  int exit_code = kOk;
  addPluginsCommand(app, exit_code);
  addDescribeCommand(app, exit_code);
  addConfigCommand(app, exit_code);
  addReferenceCommand(app, exit_code);
  addValidateCommand(app, exit_code);
  addRunCommand(app, exit_code);
  addEvalCommand(app, exit_code);
  addOptimizeCommand(app, exit_code);
  addShellCommand(app, exit_code);
  addRenderCommand(app, exit_code);
  addViewCommand(app, exit_code);
  addSweepCommand(app, exit_code);
  addMergeCommand(app, exit_code);

  app.parse_complete_callback([&] {
    // A sink, not a registered logger: runCli may run again in one process (no command, tests).
    // Its log lines go above a run's progress line, never onto it.
    std::vector<spdlog::sink_ptr> sinks{makeConsoleSink()};
    if (!log_file.empty())
      sinks.push_back(std::make_shared<spdlog::sinks::basic_file_sink_mt>(log_file, true));
    auto logger = std::make_shared<spdlog::logger>("plugslam", sinks.begin(), sinks.end());
    logger->set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");
    logger->set_level(quiet ? spdlog::level::err
                            : verbose >= 2 ? spdlog::level::trace
                            : verbose == 1 ? spdlog::level::debug
                                           : spdlog::level::info);
    spdlog::drop("plugslam");
    spdlog::set_default_logger(logger);
  });

  try {
    app.parse(argc, argv);
    if (app.get_subcommands().empty()) {
      // No command: the demo run on the built-in default config, with the global options given.
      std::vector<std::string> args{argv[0], "run"};
      for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
      std::vector<char*> ptrs;
      for (auto& a : args) ptrs.push_back(a.data());
      return runCli(static_cast<int>(ptrs.size()), ptrs.data());
    }
  } catch (const CLI::ParseError& e) {
    int rc = app.exit(e);
    return rc == 0 ? kOk : kBadInput;
  } catch (const InputError& e) {
    // One log line per line: validate lists every error of a config, one a line.
    std::istringstream lines(e.what());
    for (std::string line; std::getline(lines, line);) spdlog::error("{}", line);
    return kBadInput;
  } catch (const Error& e) {
    spdlog::error("{}", e.what());
    return kRuntimeFailure;
  } catch (const std::exception& e) {
    spdlog::error("unexpected failure: {}", e.what());
    return kRuntimeFailure;
  } catch (...) {
    spdlog::error("unexpected failure: an exception not derived from std::exception");
    return kRuntimeFailure;
  }
  return exit_code;
}

}  // namespace plugslam::runtime
