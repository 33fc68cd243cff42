#pragma once
// A sweep's results as one table: every case's result.json gathered, repeats of a grid point
// aggregated (median, min, max), the best value of each metric marked, failures listed with
// their exit code and log tail; and the same grid points of two sweep folders side by side.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "sweep/plan.h"

namespace plugslam::runtime::sweep {

struct Stats {
  double median = 0, min = 0, max = 0;
  int count = 0;
};

/// One grid point: config x dataset x parameter values, over its repeats.
struct Row {
  const Case* first = nullptr;  ///< its first repeat (labels, parameters)
  int runs = 0, ok = 0, failed = 0, missing = 0;
  std::map<std::string, Stats> metrics;  ///< only metrics with at least one value
};

/// One case's result.json, read back.
struct CaseResult {
  const Case* c = nullptr;
  bool present = false;
  std::string status, error;
  std::optional<int> exit_code;
  std::map<std::string, double> metrics;
  std::vector<std::string> log_tail;
};

struct SweepTable {
  Plan plan;
  std::vector<CaseResult> results;  ///< plan order
  std::vector<Row> rows;            ///< first-seen order of the grid points
};

/// Reads the plan and every result of a sweep folder.
SweepTable gatherResults(const std::string& dir);

/// Whether every run of grid point `r` meets every target of the plan: "yes", or "no (...)" with
/// what missed.
std::string targetVerdict(const Plan& p, const Row& r);
/// The report as Markdown: the table, the heat tables, the failed cases, the plots' files.
std::string reportMarkdown(const SweepTable& t, const std::vector<std::string>& plots);
/// One line per grid point: labels, parameters, runs, and each metric's median, min and max.
std::string tableCsv(const SweepTable& t);
/// One line per case: labels, parameters, repeat, status, exit code, metrics.
std::string casesCsv(const SweepTable& t);
/// `after` against `before`, grid point by grid point (matched by config, dataset and
/// parameters), each metric's medians and their change, as Markdown.
std::string compareMarkdown(const SweepTable& after, const SweepTable& before,
                            const std::string& after_name, const std::string& before_name);

/// Draws each metric against each swept parameter with more than one value, one line per
/// dataset (and config), into `dir`; returns the files written.
std::vector<std::string> drawPlots(const SweepTable& t, const std::string& dir);

/// Writes the report of `t` (gathered from `sweep_dir`) as report.md, table.csv, cases.csv and
/// plots/ into `out_dir` (and compare.md with a baseline); returns report.md's text.
std::string writeReport(const SweepTable& t, const std::string& sweep_dir,
                        const std::string& out_dir, const std::string& compare_dir, bool plots);

/// One line saying where and when: CPU, cores, memory, date, and the commit of the git
/// repository holding folder `repository` ("+changes" when its tracked files other than docs/
/// differ from it; "unknown" outside one).
std::string machineLine(const std::string& repository);
/// A document's section for the sweep: its title (`## `), `machine`, the commands that
/// reproduce it, its notes, and the report's tables (no pictures).
std::string sectionMarkdown(const SweepTable& t, const std::string& sweep_dir,
                            const std::string& section, const std::string& machine);
/// Replaces the text between `<!-- section:begin -->` and `<!-- section:end -->` in the Markdown
/// file `document` with `body` (appends the section when absent; the rest is kept), atomically.
void writeSection(const std::string& document, const std::string& section,
                  const std::string& body);

}  // namespace plugslam::runtime::sweep
