#pragma once
// The plugslam command line: parses argv, dispatches to the commands, maps errors to exit codes.
#include <string>

namespace plugslam::runtime {

/// Exit codes of every command.
enum ExitCode : int { kOk = 0, kRuntimeFailure = 1, kBadInput = 2, kInterrupted = 130 };

/// Runs the CLI on argv; never throws.
int runCli(int argc, char** argv);

/// The config `plugslam run` uses when given none (installed or in the source tree).
std::string defaultConfigPath();

}  // namespace plugslam::runtime
