#pragma once
// What a sweep can measure on a finished run, where each number comes from, and which way is
// better, so the report can mark the best value without knowing the metrics itself.
#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

namespace plugslam::runtime::sweep {

struct Scoring;
struct Evaluator;
struct CustomMetric;

/// Which way a metric is better; None: neither (a signed error, a count), no best is marked.
enum class Better { Lower, Higher, None };

struct MetricInfo {
  std::string name, unit, doc;
  Better better = Better::Lower;
};

/// Every metric a sweep file may name, in the order the report shows them.
const std::vector<MetricInfo>& metricTable();
/// The metric of this name, or nullptr.
const MetricInfo* findMetric(const std::string& name);

/// What the case runner knows about a finished run besides its output folder.
struct RunFacts {
  std::string out_dir;      ///< the run's -o folder (run.json, trajectory.tum, reference.tum)
  double wall_s = 0;        ///< the run process's wall time
  double peak_rss_mib = 0;  ///< its peak resident memory
  std::string cwd;          ///< where it ran: relative paths of the scoring files start there
};

/// Values (nullopt when not measurable) and, per metric without a value, why not.
struct MetricValues {
  std::map<std::string, std::optional<double>> values;
  std::map<std::string, std::string> errors;
};

/// Measures `names` on a run: run.json's figures, `plugslam eval` (the binary `self`) for
/// scores against the scoring's reference, relations or log, and the sweep file's own
/// `evaluators` for `custom` metrics. Output of the evaluations goes to `work_dir`.
MetricValues measure(const std::vector<std::string>& names, const Scoring& scoring,
                     const RunFacts& run, const std::string& self, const std::string& work_dir,
                     const std::string& source_path,
                     const std::vector<Evaluator>& evaluators = {},
                     const std::vector<CustomMetric>& custom = {});

/// "lower", "higher" or "none", and back (anything else: lower).
std::string betterName(Better b);
Better betterOf(const std::string& name);

/// What a dataset is scored against, as JSON (plan.json, case.json), and back.
nlohmann::json scoringJson(const Scoring& s);
Scoring scoringFrom(const nlohmann::json& j);

/// A sweep file's evaluators and their metrics as JSON (plan.json, case.json), and back.
nlohmann::json evaluationJson(const std::vector<Evaluator>& evaluators,
                              const std::vector<CustomMetric>& custom);
void evaluationFrom(const nlohmann::json& j, std::vector<Evaluator>& evaluators,
                    std::vector<CustomMetric>& custom);

/// The metric `name`: one of `custom`, else of metricTable(); nullptr when neither has it.
const MetricInfo* findMetric(const std::string& name, const std::vector<CustomMetric>& custom);

}  // namespace plugslam::runtime::sweep
