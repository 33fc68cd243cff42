#pragma once
// One child process of a sweep: a case's run or one of its evaluations. Its output goes to a
// log file, it runs in its own process group (so a time-out stops all of it, and Ctrl-C reaches
// it only through the sweep, which then knows not to record it), and it dies with the sweep.
#include <functional>
#include <string>
#include <vector>

namespace plugslam::runtime::sweep {

struct ProcessResult {
  int exit_code = -1;  ///< the exit status, or -1 when a signal ended it
  int signal = 0;      ///< the signal that ended it, 0 if it exited
  bool timed_out = false;
  bool interrupted = false;  ///< stopped because `stop` said so
  double wall_s = 0;
  double peak_rss_mib = 0;
  std::string error;  ///< why it could not be started (then nothing ran)
};

/// Runs argv[0] (a path) with `argv` in `cwd`, stdout and stderr appended to `log`
/// (empty: this process's own). After
/// `timeout_s` (0: never) it gets SIGTERM, 5 s later SIGKILL; when `stop()` turns true, SIGINT.
ProcessResult runProcess(const std::vector<std::string>& argv, const std::string& cwd,
                         const std::string& log, double timeout_s,
                         const std::function<bool()>& stop = {});

/// The last `lines` lines of a file (fewer if it is shorter), at most 4 KiB of it.
std::vector<std::string> tailLines(const std::string& path, size_t lines);

}  // namespace plugslam::runtime::sweep
