// --engine slurm: the missing cases as one job array; task i runs line i of a case list. Works
// wherever sbatch and squeue are on the PATH and the sweep folder and the binary are seen by the
// nodes at the same paths (a shared file system, as clusters have).
#include <fmt/format.h>

#include <boost/filesystem.hpp>
#include <chrono>
#include <fstream>
#include <iostream>
#include <thread>

#include "cli.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "sweep/engines.h"
#include "sweep/process.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;

namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

// True while squeue lists the job (queued or running). A job squeue no longer knows has ended.
bool jobActive(const std::string& squeue, const std::string& job, const std::string& dir) {
  const std::string log = dir + "/squeue.out";
  boost::system::error_code ec;
  fs::remove(log, ec);
  const ProcessResult p = runProcess({squeue, "-h", "-j", job, "-o", "%i"}, "", log, 30);
  return p.exit_code == 0 && !readAll(log).empty();
}

}  // namespace

int runSlurm(const Plan& plan, const EngineOptions& options) {
  const std::string sbatch = findOnPath("sbatch"), squeue = findOnPath("squeue");
  if (sbatch.empty() || squeue.empty())
    throw InputError("--engine slurm needs sbatch and squeue on the PATH (Slurm's client); "
                     "scripts/slurm-local.sh start brings up a one-node cluster on this machine");
  const fs::path sdir = fs::path(options.dir) / "slurm";
  fs::create_directories(sdir);
  const std::string last_job_file = (sdir / "last_job").string();
  // A job of an earlier `--no-wait` still running holds cases that have no result yet:
  // submitting them again would run them twice, into the same folders.
  if (fs::exists(last_job_file)) {
    const std::string last = readAll(last_job_file);
    if (!last.empty() && jobActive(squeue, last, sdir.string()))
      throw InputError(fmt::format(
          "job {} of this sweep is still queued or running (squeue -j {}): wait for it, or "
          "scancel {}, then run the sweep again to submit the cases it left without a result",
          last, last, last));
  }
  const auto pending = pendingCases(plan, options.dir);
  std::cout << fmt::format("{} cases, {} with a result; {} to submit\n", plan.cases.size(),
                           plan.cases.size() - pending.size(), pending.size())
            << std::flush;
  if (pending.empty()) return kOk;

  int n = 1;
  while (fs::exists(sdir / fmt::format("cases-{}.txt", n))) ++n;
  const std::string list = (sdir / fmt::format("cases-{}.txt", n)).string();
  const std::string script = (sdir / fmt::format("job-{}.sh", n)).string();
  std::string lines;
  for (const Case* c : pending) lines += caseDir(options.dir, c->id) + "\n";
  writeFileAtomically(list, lines);
  writeFileAtomically(
      script, fmt::format("#!/bin/sh\n"
                          "# Task i of the array runs the case on line i of {} (0-based).\n"
                          "exec {} sweep case --list {} --index \"$SLURM_ARRAY_TASK_ID\"\n",
                          list, shellQuote(options.self), shellQuote(list)));
  fs::permissions(script, fs::perms::owner_all | fs::perms::group_read | fs::perms::others_read);

  const SlurmOptions& s = options.slurm;
  std::string array = fmt::format("0-{}", pending.size() - 1);
  if (s.max_parallel > 0) array += fmt::format("%{}", s.max_parallel);
  std::vector<std::string> argv{sbatch, "--parsable", "--job-name=plugslam-sweep",
                                "--array=" + array,
                                "--output=" + (sdir / fmt::format("job-{}-%a.out", n)).string()};
  if (!s.partition.empty()) argv.push_back("--partition=" + s.partition);
  if (!s.time.empty()) argv.push_back("--time=" + s.time);
  if (!s.mem.empty()) argv.push_back("--mem=" + s.mem);
  if (!s.account.empty()) argv.push_back("--account=" + s.account);
  if (s.cpus > 0) argv.push_back(fmt::format("--cpus-per-task={}", s.cpus));
  argv.insert(argv.end(), s.extra.begin(), s.extra.end());
  argv.push_back(script);
  const std::string submit_log = (sdir / fmt::format("sbatch-{}.out", n)).string();
  const ProcessResult p = runProcess(argv, fs::current_path().string(), submit_log, 120);
  const std::string said = readAll(submit_log);
  if (p.exit_code != 0)
    throw Error(fmt::format("sbatch failed (exit {}): {}", p.exit_code, said));
  // --parsable prints "id" or "id;cluster".
  const std::string job = said.substr(said.find_last_of('\n') == std::string::npos ? 0 : said.find_last_of('\n') + 1);
  const std::string job_id = job.substr(0, job.find(';'));
  writeFileAtomically(last_job_file, job_id + "\n");
  std::cout << fmt::format("submitted job array {} ({} tasks; script {}, task logs {}/job-{}-N.out)\n",
                           job_id, pending.size(), script, sdir.string(), n)
            << std::flush;
  if (!options.wait) {
    std::cout << fmt::format(
        "not waiting: `squeue -j {0}` shows it; once it is gone, `plugslam sweep report {1}`; "
        "the same `sweep run` again submits only the cases still without a result\n",
        job_id, options.dir);
    return kOk;
  }
  InterruptScope scope;
  size_t shown = plan.cases.size() - pending.size();
  const auto start = std::chrono::steady_clock::now();
  for (;;) {
    const bool active = jobActive(squeue, job_id, sdir.string());
    const size_t done = plan.cases.size() - pendingCases(plan, options.dir).size();
    if (done != shown) {
      shown = done;
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::cout << fmt::format("  {}/{} cases have a result ({:.0f} s)\n", done, plan.cases.size(), t)
                << std::flush;
    }
    if (!active) break;
    for (int i = 0; i < 10 && !interruptFlag(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (interruptFlag()) {
      std::cout << fmt::format("stopped waiting; job {} goes on (scancel {} stops it)\n", job_id, job_id);
      return kInterrupted;
    }
  }
  const size_t missing = pendingCases(plan, options.dir).size();
  if (missing > 0) {
    std::cout << fmt::format(
        "job {} ended with {} cases without a result (a task ended before writing one: a lost "
        "node, the job's time limit; see {}/job-{}-N.out); running the sweep again submits only "
        "those\n",
        job_id, missing, sdir.string(), n);
    return kRuntimeFailure;
  }
  std::cout << fmt::format("done: job {}, every case has a result\n", job_id);
  return kOk;
}

}  // namespace plugslam::runtime::sweep
