#pragma once
// A sweep file: which configs run on which inputs with which parameter values, how often, and
// what is measured on each result. Read like a config: every error names the file, line, column
// and key, unknown keys are errors, and one read reports every error it finds.
#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <vector>

#include "sweep/metrics.h"

namespace plugslam::runtime::sweep {

/// Where a value was written: for errors that are found later (a grid key the config rejects).
struct Origin {
  int line = 0, column = 0;
};

/// One `--set` the sweep applies: the key as written, the value as YAML text.
struct Override {
  std::string key, value;
  Origin origin;
  std::string text() const { return key + "=" + value; }
};

/// What a dataset's results are scored against (empty: what the run itself wrote).
struct Scoring {
  std::string reference;  ///< trajectory file for ate, rpe and relations
  std::string relations;  ///< relations file for the relations metric
  std::string log;        ///< log for crispness and coverage (empty: the source.path override)
  std::string laser;      ///< the log's laser entry for crispness (empty: eval's default)
  std::vector<std::string> evaluate;  ///< the file's evaluators run on it (empty: every one)
};

/// A named input: the overrides that select it and what its results are scored against.
struct Dataset {
  std::string name;
  std::vector<size_t> configs;  ///< indices into SweepFile::configs (empty: the file's `config`)
  std::vector<Override> set;
  Scoring scoring;
  Origin origin;
};

/// A bound a metric must meet in every run of a grid point (`targets`: the report's pass column):
/// a number, or a factor times another metric of the same run (the reference's own score).
struct Target {
  std::string metric;
  bool at_most = true;  ///< "<= value"; false: ">= value"
  double value = 0;     ///< the bound, or the factor of `of`
  std::string of;       ///< the metric the bound is a multiple of (empty: `value` is the bound)
  std::string text() const;  ///< "ate <= 0.05", "coverage >= 0.9 * coverage_ref"
};

/// A command run on each finished run (`evaluators`): a shell command line whose standard output
/// is JSON, with {out}, {trajectory}, {reference}, {source} and {case} replaced by the run's
/// folder, its trajectory.tum, the dataset's reference (else the run's reference.tum), its
/// source.path and the case's folder.
struct Evaluator {
  std::string name, command;
};

/// A metric an evaluator gives: the number at `key` (a path as `--set` writes one) of its output.
struct CustomMetric {
  MetricInfo info;
  std::string evaluator, key;
};

/// One swept axis: a single key (grid) or keys whose values go together (zip).
struct Axis {
  std::vector<std::string> keys;
  std::vector<Origin> origins;                    ///< per key
  std::vector<std::vector<std::string>> values;   ///< values[i][k]: point i, key k (YAML text)
};

/// Where Slurm runs it (each is also a flag of `sweep run`, which wins).
struct SlurmOptions {
  std::string partition, time, mem, account;
  int cpus = 0;          ///< --cpus-per-task (0: the cluster's default)
  int max_parallel = 0;  ///< the array's %N throttle (0: none)
  std::vector<std::string> extra;  ///< more sbatch arguments, verbatim
};

/// What a plan keeps of its sweep file, as the file states it: the metrics and the evaluations
/// that give some of them, the per-run timeout, and what the report judges and titles.
struct SweepSettings {
  std::vector<std::string> metrics;
  std::vector<Evaluator> evaluators;        ///< the file's own evaluations
  std::vector<CustomMetric> custom_metrics;  ///< the metrics they give
  double timeout_s = 0;                      ///< per run (0: none)
  std::string title, notes;     ///< of the report's section in a document (not of any case)
  std::vector<Target> targets;  ///< judged by the report (not part of any case)
};

struct SweepFile : SweepSettings {
  std::string file;                  ///< as given
  std::vector<std::string> configs;  ///< absolute paths: the file's `config`, then datasets' own
  std::vector<Origin> config_origins;
  size_t shared_configs = 0;         ///< configs[0..this) are the file's `config` list
  std::vector<Dataset> datasets;     ///< at least one (an unnamed one when the file has none)
  std::vector<Override> set;         ///< applied to every case, before the dataset's
  std::vector<Axis> axes;            ///< grid keys first (one axis each), then zip groups
  int repeat = 1;
  SlurmOptions slurm;
  std::vector<std::string> hosts;  ///< for --engine parallel
  /// Whether dataset `d` runs with configs[config] (its own configs, else the file's).
  bool runs(size_t config, const Dataset& d) const;
};

/// Reads and checks a sweep file; throws ConfigError (one error) or ConfigErrorList. Relative
/// config paths are looked up beside the sweep file, then in the current folder, then among the
/// shipped configs.
SweepFile readSweepFile(const std::string& path);
/// Parses sweep text; `name` stands for the file in errors and relative paths.
SweepFile parseSweep(const std::string& text, const std::string& name);

/// `plugslam describe sweep`: the keys of a sweep file.
std::string describeSweepFile();

}  // namespace plugslam::runtime::sweep
