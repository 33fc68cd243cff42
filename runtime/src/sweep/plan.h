#pragma once
// A sweep file expanded into cases: every config x dataset x grid point x repeat, in that order,
// each with the exact command line that runs it and its content id. A plan folder holds
// plan.json (the cases in order, what the report reads), cases.tsv (the numbered list),
// commands.sh (every case's command line) and cases/ID/ per case: case.json (its `command` to
// paste into a shell, what `sweep case` runs and measures) and, once it ran, result.json
// (written atomically: present means finished).
#include <string>
#include <utility>
#include <vector>

#include "sweep/sweep_file.h"

namespace plugslam::runtime {
class PluginManager;
}

namespace plugslam::runtime::sweep {

struct Case {
  std::string id;
  std::string config;        ///< absolute path
  std::string config_label;  ///< the file name, or more of its path where two share a name
  std::string dataset;
  std::vector<std::pair<std::string, std::string>> params;  ///< swept key -> value, axis order
  int repeat = 1;                                           ///< 1-based
  std::vector<std::string> overrides;  ///< "key=value": set, dataset, swept, in that order
  std::string source_path;             ///< the source.path override, if any (crispness's log)
  Scoring scoring;
  /// The grid point without the repeat: what the report aggregates repeats over.
  std::string groupKey() const;
};

struct Plan : SweepSettings {
  std::string sweep_file;
  std::vector<std::string> swept_keys;
  std::vector<std::string> config_labels, datasets;  ///< in file order
  std::vector<Case> cases;
};

/// "N configs x M datasets", or "K config-dataset pairs" where datasets name their own configs
/// (not the full product).
std::string runsOn(const Plan& plan);

/// Expands the file (resolving each config once, for its text and id); no module is built.
Plan expandSweep(const SweepFile& sweep);

/// Builds every config with every dataset, and every swept value once, as `plugslam validate`
/// does: a key that is not a parameter or a value that does not fit is an error located in the
/// sweep file, before anything runs.
void validateSweep(const SweepFile& sweep, PluginManager& plugins);

/// What a case runs: argv of `plugslam run`, in `cwd`.
struct CaseCommand {
  std::vector<std::string> argv;
  std::string cwd;
};
CaseCommand caseCommand(const Case& c, const std::string& self, const std::string& case_dir,
                        const std::string& cwd);

/// Writes plan.json, cases.tsv, commands.sh and each case's folder (case.json) under `dir`; results already
/// there are kept. `self` is the plugslam binary the cases run.
void writePlan(const Plan& plan, const std::string& dir, const std::string& self);
/// Reads a plan folder's plan.json.
Plan readPlan(const std::string& dir);

/// DIR/cases/ID.
std::string caseDir(const std::string& dir, const std::string& id);
/// True when the case has a result (finished, failed or timed out).
bool hasResult(const std::string& dir, const std::string& id);

/// A word for a shell: quoted unless it needs none.
std::string shellQuote(const std::string& word);

}  // namespace plugslam::runtime::sweep
