// --engine parallel --hosts H1,H2: GNU parallel spreads the missing cases over ssh logins (":"
// is this machine). The hosts see the sweep folder and the binary at the same paths (a shared
// folder); they need ssh access without a password and nothing else.
#include <fmt/format.h>

#include <boost/filesystem.hpp>
#include <cstdlib>
#include <iostream>

#include "cli.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "sweep/engines.h"
#include "sweep/process.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;

int runParallel(const Plan& plan, const EngineOptions& options) {
  const std::string parallel = findOnPath("parallel");
  if (parallel.empty())
    throw InputError("--engine parallel needs GNU parallel on the PATH (Debian: apt-get install parallel)");
  if (options.hosts.empty())
    throw InputError("--engine parallel needs --hosts H1,H2 (or `hosts:` in the sweep file); ':' is this machine");
  const auto pending = pendingCases(plan, options.dir);
  std::string hosts;
  for (const auto& h : options.hosts) hosts += (hosts.empty() ? "" : ",") + h;
  std::cout << fmt::format("{} cases, {} with a result; running {} through GNU parallel on {}\n",
                           plan.cases.size(), plan.cases.size() - pending.size(), pending.size(),
                           hosts)
            << std::flush;
  if (pending.empty()) return kOk;
  const fs::path pdir = fs::path(options.dir) / "parallel";
  fs::create_directories(pdir);
  int n = 1;
  while (fs::exists(pdir / fmt::format("cases-{}.txt", n))) ++n;
  const std::string list = (pdir / fmt::format("cases-{}.txt", n)).string();
  std::string lines;
  for (const Case* c : pending) lines += caseDir(options.dir, c->id) + "\n";
  writeFileAtomically(list, lines);
  std::vector<std::string> argv{parallel, "--will-cite", "--halt", "never", "--joblog",
                                (pdir / fmt::format("joblog-{}.txt", n)).string(), "-S", hosts,
                                "-a", list};
  if (options.jobs > 0) argv.insert(argv.end(), {"-j", std::to_string(options.jobs)});
  // An ssh login starts with its own environment: the variables a run reads go along.
  for (const char* var : {"PLUGSLAM_DATA", "PLUGSLAM_PLUGIN_PATH"})
    if (const char* v = std::getenv(var); v && *v) argv.insert(argv.end(), {"--env", var});
  // parallel joins the command's words with spaces and hands them to a shell.
  argv.push_back(shellQuote(options.self) + " sweep case {}");
  FolderLock folder_lock(options.dir);
  InterruptScope scope;
  const ProcessResult p = runProcess(argv, fs::current_path().string(), "", 0,
                                     [] { return interruptFlag().load(); });
  if (p.interrupted) {
    std::cout << "interrupted: the cases stopped midway have no result; running the sweep "
                 "again runs only the missing ones\n";
    return kInterrupted;
  }
  if (p.exit_code < 0 || p.exit_code == 255 || !p.error.empty())
    throw Error(fmt::format("GNU parallel failed (exit {}{})", p.exit_code, p.error.empty() ? "" : ": " + p.error));
  const size_t missing = pendingCases(plan, options.dir).size();
  if (missing > 0) {
    std::cout << fmt::format(
        "{} cases have no result (a host lost, or `sweep case` failed: see {}/joblog-{}.txt); "
        "running the sweep again runs only those\n",
        missing, pdir.string(), n);
    return kRuntimeFailure;
  }
  std::cout << "done: every case has a result\n";
  return kOk;
}

}  // namespace plugslam::runtime::sweep
