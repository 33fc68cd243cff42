#pragma once
// Runs one planned case where it stands (this machine, a Slurm node, an ssh host): its
// `plugslam run`, then its metrics, then result.json, written atomically as the last step, so a
// case has a result exactly when it finished; a case stopped by Ctrl-C or by its engine leaves
// none and runs again next time.
#include <functional>
#include <string>

namespace plugslam::runtime::sweep {

struct CaseOutcome {
  std::string status;  ///< ok, failed, timeout; "interrupted" (nothing recorded)
  int exit_code = 0;
  double wall_s = 0;
};

/// Runs the case of `case_dir` (its case.json). `stop` turning true interrupts the run.
CaseOutcome runCase(const std::string& case_dir, const std::function<bool()>& stop = {});

}  // namespace plugslam::runtime::sweep
