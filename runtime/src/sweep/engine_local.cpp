// --engine local -j N: N cases at a time on this machine, each in its own process.
#include <fmt/format.h>

#include <iostream>
#include <mutex>
#include <thread>

#include "cli.h"
#include "sweep/case_runner.h"
#include "sweep/engines.h"

namespace plugslam::runtime::sweep {

std::string caseLabel(const Case& c) {
  std::string label = c.config_label + " " + c.dataset;
  for (const auto& [k, v] : c.params) label += " " + k + "=" + v;
  if (c.repeat > 1) label += fmt::format(" #{}", c.repeat);
  return label;
}

int runLocal(const Plan& plan, const EngineOptions& options) {
  const auto pending = pendingCases(plan, options.dir);
  const size_t done_before = plan.cases.size() - pending.size();
  int jobs = options.jobs > 0 ? options.jobs : static_cast<int>(std::thread::hardware_concurrency());
  jobs = std::max(1, std::min<int>(jobs, static_cast<int>(pending.size())));
  std::cout << fmt::format("{} cases, {} with a result; running {} on this machine, {} at a time\n",
                           plan.cases.size(), done_before, pending.size(), jobs)
            << std::flush;
  if (pending.empty()) return kOk;
  FolderLock folder_lock(options.dir);
  InterruptScope scope;
  std::atomic<size_t> next{0};
  std::mutex print;
  size_t finished = 0, failed = 0, errors = 0;
  const auto stop = [] { return interruptFlag().load(); };
  const auto worker = [&] {
    for (;;) {
      if (stop()) return;
      const size_t i = next++;
      if (i >= pending.size()) return;
      const Case& c = *pending[i];
      CaseOutcome o;
      std::string error;
      try {
        o = runCase(caseDir(options.dir, c.id), stop);
      } catch (const std::exception& e) {
        error = e.what();
      }
      std::lock_guard<std::mutex> lock(print);
      if (o.status == "interrupted") continue;
      if (!error.empty()) ++errors;
      else ++finished;
      if (o.status != "ok" && error.empty()) ++failed;
      std::cout << fmt::format("[{}/{}] {} {}: {}", finished + errors, pending.size(), c.id, caseLabel(c),
                               error.empty() ? o.status : "error: " + error);
      if (o.status == "failed") std::cout << fmt::format(" (exit {})", o.exit_code);
      std::cout << fmt::format(" {:.1f} s\n", o.wall_s) << std::flush;
    }
  };
  std::vector<std::thread> threads;
  for (int t = 0; t < jobs; ++t) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
  if (interruptFlag()) {
    std::cout << fmt::format(
        "interrupted: {} of {} cases ran ({} failed); the cases stopped midway have no result, "
        "and running the sweep again runs only the missing ones\n",
        finished, pending.size(), failed);
    return kInterrupted;
  }
  std::cout << fmt::format("done: {} cases ran, {} of them failed or timed out (the report lists them)\n",
                           finished, failed);
  if (errors > 0) {
    std::cout << fmt::format("{} cases could not be run and have no result (see above); running "
                             "the sweep again runs only those\n",
                             errors);
    return kRuntimeFailure;
  }
  return kOk;
}

}  // namespace plugslam::runtime::sweep
