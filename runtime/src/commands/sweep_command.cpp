// plugslam sweep plan|run|report|case: configs x datasets x parameter grids, run by an engine
// that exists (this machine, Slurm, GNU parallel), gathered into one table.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/filesystem.hpp>
#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>

#include "cli.h"
#include "commands/commands.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "sweep/case_runner.h"
#include "sweep/engines.h"
#include "sweep/plan.h"
#include "sweep/report.h"
#include "sweep/sweep_file.h"

namespace plugslam::runtime {

namespace {

namespace fs = boost::filesystem;

struct SweepArgs {
  std::string file, dir, engine = "local", compare, report_dir, list, section,
      document = "docs/benchmarks.md";
  int jobs = 0, index = -1;
  bool no_wait = false, no_plots = false;
  std::string hosts;
  sweep::SlurmOptions slurm;
};

// Reads, checks against the configs, expands and writes the plan: nothing runs before all of it
// holds.
sweep::Plan planInto(const sweep::SweepFile& file, const SweepArgs& a) {
  {
    PluginManager plugins;
    sweep::validateSweep(file, plugins);
  }
  sweep::Plan plan = sweep::expandSweep(file);
  sweep::writePlan(plan, a.dir, boost::dll::program_location().string());
  size_t done = 0;
  for (const auto& c : plan.cases) done += sweep::hasResult(a.dir, c.id);
  size_t points = 1;
  for (const auto& axis : file.axes) points *= axis.values.size();
  std::cout << fmt::format("planned {} cases ({} x {} grid points x {} repeats) in {}: {} have "
                           "a result\n",
                           plan.cases.size(), sweep::runsOn(plan), points, file.repeat, a.dir,
                           done)
            << std::flush;
  return plan;
}

}  // namespace

void addSweepCommand(CLI::App& root, int& exit_code) {
  auto* cmd = root.add_subcommand(
      "sweep", "Configs x datasets x parameter grids, here, on Slurm or over ssh");
  cmd->footer("`plugslam describe sweep`: the keys of a sweep file; docs/sweeps.md: the engines.");
  cmd->require_subcommand(1);
  static SweepArgs a;

  auto* plan = cmd->add_subcommand(
      "plan", "Expand a sweep file into numbered cases, each a folder with its exact command line "
              "and a content id; nothing runs");
  plan->add_option("FILE", a.file, "sweep file (YAML)")->required();
  plan->add_option("-o,--output", a.dir, "sweep folder")->required();
  plan->callback([&exit_code] {
    planInto(sweep::readSweepFile(a.file), a);
    std::cout << fmt::format("the cases: {0}/cases.tsv; their command lines: {0}/commands.sh and {0}/cases/ID/case.json\n", a.dir);
    exit_code = kOk;
  });

  auto* run = cmd->add_subcommand(
      "run", "Plan into DIR, then run every case that has no result yet, with an engine");
  run->add_option("FILE", a.file, "sweep file (YAML)")->required();
  run->add_option("-o,--output", a.dir, "sweep folder")->required();
  run->add_option("--engine", a.engine, "local (this machine), slurm (one job array), parallel (GNU parallel over ssh)")
      ->check(CLI::IsMember({"local", "slurm", "parallel"}))
      ->capture_default_str();
  run->add_option("-j,--jobs", a.jobs,
                  "local: cases at once (default: one per core); parallel: jobs per host "
                  "(default: parallel's, one per core)")
      ->check(CLI::NonNegativeNumber);
  run->add_option("--partition", a.slurm.partition, "slurm: partition (default: the file's slurm.partition)");
  run->add_option("--time", a.slurm.time, "slurm: time limit of each task, e.g. 00:30:00");
  run->add_option("--mem", a.slurm.mem, "slurm: memory of each task, e.g. 4G");
  run->add_option("--account", a.slurm.account, "slurm: account to charge");
  run->add_option("--cpus", a.slurm.cpus, "slurm: cpus per task")->check(CLI::NonNegativeNumber);
  run->add_option("--max-parallel", a.slurm.max_parallel, "slurm: tasks of the array at once (%N)")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--no-wait", a.no_wait, "slurm: submit and return (default: wait for the array)");
  run->add_flag("--wait", [](int64_t) { a.no_wait = false; }, "slurm: wait for the array (the default)");
  run->add_option("--hosts", a.hosts, "parallel: ssh logins, comma separated (':' is this machine)");
  run->callback([&exit_code] {
    const sweep::SweepFile file = sweep::readSweepFile(a.file);
    const sweep::Plan plan = planInto(file, a);
    sweep::EngineOptions o;
    o.dir = fs::absolute(a.dir).string();
    o.self = boost::dll::program_location().string();
    o.jobs = a.jobs;
    o.wait = !a.no_wait;
    o.slurm = file.slurm;
    // Flags win over the file.
    if (!a.slurm.partition.empty()) o.slurm.partition = a.slurm.partition;
    if (!a.slurm.time.empty()) o.slurm.time = a.slurm.time;
    if (!a.slurm.mem.empty()) o.slurm.mem = a.slurm.mem;
    if (!a.slurm.account.empty()) o.slurm.account = a.slurm.account;
    if (a.slurm.cpus > 0) o.slurm.cpus = a.slurm.cpus;
    if (a.slurm.max_parallel > 0) o.slurm.max_parallel = a.slurm.max_parallel;
    o.hosts = file.hosts;
    if (!a.hosts.empty()) {
      o.hosts.clear();
      std::stringstream list(a.hosts);
      for (std::string h; std::getline(list, h, ',');)
        if (!h.empty()) o.hosts.push_back(h);
    }
    if (a.engine == "local") exit_code = sweep::runLocal(plan, o);
    else if (a.engine == "slurm") exit_code = sweep::runSlurm(plan, o);
    else exit_code = sweep::runParallel(plan, o);
    if (exit_code == kOk) std::cout << "`plugslam sweep report " << a.dir << "` gathers the table\n";
  });

  auto* report = cmd->add_subcommand(
      "report", "Gather a sweep folder's results: a table (CSV, Markdown), best values marked, "
                "repeats aggregated, plots; --compare DIR2 matches another sweep's grid points");
  report->add_option("DIR", a.dir, "sweep folder")->required();
  report->add_option("-o,--output", a.report_dir, "where report.md, table.csv, cases.csv and plots/ go (default: DIR/report)");
  report->add_option("--compare", a.compare, "a sweep folder to compare with (before), grid point by grid point");
  report->add_flag("--no-plots", a.no_plots, "no pictures");
  report->add_option("--section", a.section,
                     "also write the tables into this section of --doc (title, machine, commands)");
  report->add_option("--doc", a.document, "the Markdown document of --section")
      ->capture_default_str();
  report->callback([&exit_code] {
    const std::string out = a.report_dir.empty() ? (fs::path(a.dir) / "report").string() : a.report_dir;
    const sweep::SweepTable t = sweep::gatherResults(a.dir);
    std::cout << sweep::writeReport(t, a.dir, out, a.compare, !a.no_plots);
    std::cout << fmt::format("\nwrote {0}/report.md, {0}/table.csv, {0}/cases.csv{1}\n", out,
                             a.no_plots ? "" : ", " + out + "/plots/");
    if (!a.section.empty()) {
      const fs::path doc = fs::absolute(a.document);
      sweep::writeSection(doc.string(), a.section,
                          sweep::sectionMarkdown(t, a.dir, a.section,
                                                 sweep::machineLine(doc.parent_path().string())));
      std::cout << "wrote section '" << a.section << "' of " << a.document << "\n";
    }
    exit_code = kOk;
  });

  auto* one = cmd->add_subcommand(
      "case", "Run one planned case and record its result (what every engine runs per case)");
  one->add_option("CASE_DIR", a.dir, "the case's folder (DIR/cases/ID)");
  one->add_option("--list", a.list, "a file of case folders, one a line (with --index)");
  one->add_option("--index", a.index, "the 0-based line of --list to run (a job array's task id)");
  one->callback([&exit_code] {
    std::string case_dir = a.dir;
    if (!a.list.empty()) {
      if (a.index < 0) throw InputError("sweep case --list needs --index");
      std::ifstream in(a.list);
      if (!in) throw InputError("cannot read '" + a.list + "'");
      std::string line;
      for (int i = 0; std::getline(in, line); ++i)
        if (i == a.index) break;
      if (!in) throw InputError(fmt::format("'{}' has no line {}", a.list, a.index));
      case_dir = line;
    }
    if (case_dir.empty()) throw InputError("sweep case needs CASE_DIR or --list FILE --index I");
    sweep::InterruptScope scope;
    const sweep::CaseOutcome o = sweep::runCase(case_dir, [] { return sweep::interruptFlag().load(); });
    std::cout << fmt::format("{}: {}{} {:.1f} s\n", fs::path(case_dir).filename().string(), o.status,
                             o.status == "failed" ? fmt::format(" (exit {})", o.exit_code) : "", o.wall_s);
    exit_code = o.status == "interrupted" ? kInterrupted : kOk;
  });
}

}  // namespace plugslam::runtime
