#pragma once
// One function per subcommand. Each adds its subcommand to the root app; the subcommand's
// callback does the work and stores its exit code in `exit_code`. Errors are thrown as
// plugslam::Error (InputError -> exit 2, others -> exit 1) and mapped by runCli.
namespace CLI {
class App;
}

namespace plugslam::runtime {

void addPluginsCommand(CLI::App& root, int& exit_code);
void addDescribeCommand(CLI::App& root, int& exit_code);
void addConfigCommand(CLI::App& root, int& exit_code);
void addReferenceCommand(CLI::App& root, int& exit_code);
void addValidateCommand(CLI::App& root, int& exit_code);
void addRunCommand(CLI::App& root, int& exit_code);
void addEvalCommand(CLI::App& root, int& exit_code);
void addOptimizeCommand(CLI::App& root, int& exit_code);
void addShellCommand(CLI::App& root, int& exit_code);
void addRenderCommand(CLI::App& root, int& exit_code);
void addViewCommand(CLI::App& root, int& exit_code);
void addSweepCommand(CLI::App& root, int& exit_code);
void addMergeCommand(CLI::App& root, int& exit_code);

}  // namespace plugslam::runtime
