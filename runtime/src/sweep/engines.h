#pragma once
// The engines that run a plan's missing cases. None schedules anything itself: each hands the
// cases to something that exists (threads here, one Slurm job array, GNU parallel over ssh), and
// every case runs through `plugslam sweep case`, so a result means the same whatever ran it.
#include <atomic>
#include <string>
#include <vector>

#include "sweep/plan.h"
#include "sweep/sweep_file.h"

namespace plugslam::runtime::sweep {

struct EngineOptions {
  std::string dir;   ///< the sweep folder, absolute
  std::string self;  ///< the plugslam binary, absolute
  int jobs = 0;      ///< local: cases at once (0: one per core); parallel: per host (0: its default)
  bool wait = true;  ///< slurm: wait for the array to finish
  SlurmOptions slurm;
  std::vector<std::string> hosts;  ///< parallel: ssh logins (":" is this machine)
};

/// The cases that have no result yet, in plan order.
std::vector<const Case*> pendingCases(const Plan& plan, const std::string& dir);

/// Set by SIGINT/SIGTERM while an engine runs; engines stop starting cases and stop their runs.
std::atomic<bool>& interruptFlag();
/// Installs the handlers that set interruptFlag() for the life of the object.
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  struct Saved;
  Saved* saved_;
};

/// Holds DIR/.sweep.lock while an engine runs cases here: a second sweep started on the same
/// folder would run the same missing cases into the same folders. Throws InputError when held.
class FolderLock {
 public:
  explicit FolderLock(const std::string& dir);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

/// Each returns the exit code of `sweep run`: 0 when every case has a result (failed ones
/// included), 130 when interrupted, 1 when cases are left without a result.
int runLocal(const Plan& plan, const EngineOptions& options);
int runSlurm(const Plan& plan, const EngineOptions& options);
int runParallel(const Plan& plan, const EngineOptions& options);

/// "config dataset key=value ... #repeat": how progress lines and the report name a case.
std::string caseLabel(const Case& c);

/// A file on the PATH, or "".
std::string findOnPath(const std::string& program);

}  // namespace plugslam::runtime::sweep
