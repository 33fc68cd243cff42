#include "sweep/case_runner.h"

#include <fmt/format.h>
#include <unistd.h>

#include <boost/filesystem.hpp>
#include <chrono>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "sweep/metrics.h"
#include "sweep/process.h"
#include "sweep/sweep_file.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;
using nlohmann::json;

namespace {

std::string hostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

std::string utcNow() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&t, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace

CaseOutcome runCase(const std::string& case_dir, const std::function<bool()>& stop) {
  const std::string case_file = case_dir + "/case.json";
  std::ifstream in(case_file);
  if (!in) throw InputError("no case at '" + case_dir + "' (no case.json)");
  json c;
  try {
    c = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(case_file + ": " + e.what());
  }
  const auto argv = c.at("argv").get<std::vector<std::string>>();
  const std::string cwd = c.value("cwd", "");
  const std::string out_dir = case_dir + "/out";
  const std::string log = case_dir + "/log.txt";
  // What an earlier, interrupted attempt left is not this attempt's.
  boost::system::error_code ec;
  fs::remove_all(out_dir, ec);
  fs::remove(log, ec);
  fs::remove(case_dir + "/eval.log", ec);

  const ProcessResult p = runProcess(argv, cwd, log, c.value("timeout_s", 0.0), stop);
  // Nothing ran: no result, so the next sweep tries again (a binary being rebuilt, a host
  // without the shared folder).
  if (!p.error.empty()) throw Error(p.error);
  CaseOutcome outcome;
  outcome.exit_code = p.exit_code;
  outcome.wall_s = p.wall_s;
  if (p.interrupted) {
    outcome.status = "interrupted";
    return outcome;
  }
  outcome.status = p.timed_out ? "timeout" : p.exit_code == 0 ? "ok" : "failed";
  json result{{"id", c.value("id", "")},
              {"status", outcome.status},
              {"exit_code", p.exit_code >= 0 ? json(p.exit_code) : json(nullptr)},
              {"signal", p.signal},
              {"wall_s", p.wall_s},
              {"peak_rss_mib", p.peak_rss_mib},
              {"host", hostName()},
              {"finished_at", utcNow()}};
  if (p.timed_out) result["error"] = fmt::format("stopped after the timeout of {:g} s", c.value("timeout_s", 0.0));
  json metrics = json::object(), errors = json::object();
  if (outcome.status == "ok") {
    const Scoring scoring = scoringFrom(c.value("scoring", json::object()));
    RunFacts facts{out_dir, p.wall_s, p.peak_rss_mib, cwd};
    std::vector<Evaluator> evaluators;
    std::vector<CustomMetric> custom;
    evaluationFrom(c.value("evaluation", json::object()), evaluators, custom);
    const MetricValues m = measure(c.value("metrics", std::vector<std::string>{}), scoring, facts,
                                   argv.at(0), case_dir, c.value("source_path", ""), evaluators,
                                   custom);
    for (const auto& [name, v] : m.values) metrics[name] = v ? json(*v) : json(nullptr);
    for (const auto& [name, why] : m.errors) errors[name] = why;
  } else {
    result["log_tail"] = tailLines(log, 15);
  }
  result["metrics"] = metrics;
  if (!errors.empty()) result["metric_errors"] = errors;
  writeFileAtomically(case_dir + "/result.json", result.dump(2) + "\n");
  return outcome;
}

}  // namespace plugslam::runtime::sweep
