#include "sweep/metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/filesystem.hpp>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "config_builder.h"
#include "sweep/plan.h"
#include "sweep/process.h"
#include "sweep/sweep_file.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;
using nlohmann::json;

const std::vector<MetricInfo>& metricTable() {
  static const std::vector<MetricInfo> table{
      {"ate", "m",
       "absolute trajectory error, RMSE: against the dataset's reference, else the run's own "
       "(run.json)",
       Better::Lower},
      {"rpe", "m",
       "relative pose error over 1 m of travel, RMSE: against the dataset's reference, else the "
       "run's own",
       Better::Lower},
      {"relations", "m",
       "relation error, mean translation: the dataset's relations file, else relations built "
       "from its reference or the run's reference.tum",
       Better::Lower},
      {"relations_deg", "deg", "relation error, mean rotation (as relations)", Better::Lower},
      {"relations_unused", "",
       "relations that found no pose to score (as relations; eval relations says why)",
       Better::Lower},
      {"crispness", "m",
       "map crispness (no ground truth): the dataset's log, else its source.path; no value "
       "where no scan overlaps one far enough apart",
       Better::Lower},
      {"coverage", "",
       "the share of scan points that crispness matched", Better::Higher},
      {"crispness_ref", "m",
       "crispness of the reference (the dataset's, else the run's reference.tum) on the same "
       "scans: what a target compares crispness with",
       Better::Lower},
      {"coverage_ref", "", "the reference's coverage (as crispness_ref)", Better::Higher},
      {"components", "", "pieces of the pose graph, 1 when all of it is connected (run.json)",
       Better::Lower},
      {"hz", "Hz", "frames per second of the whole run (run.json)", Better::Higher},
      {"pipeline_hz", "Hz", "frames per second inside the pipeline (run.json)", Better::Higher},
      {"memory", "MiB", "peak resident memory of the run", Better::Lower},
      {"time", "s", "wall time of the run", Better::Lower},
      {"tracking_failures", "", "frames the tracker lost (run.json)", Better::Lower},
      {"ambiguous", "",
       "frames whose search found a rival pose nearly as good (run.json tracking_ambiguous)",
       Better::Lower},
      {"search_s", "s", "time in the aligner's correlative search (run.json)", Better::Lower},
      {"refine_s", "s", "time in the aligner's solve (run.json)", Better::Lower},
      {"merge_s", "s", "time merging frames into local maps (run.json)", Better::Lower},
      {"loops", "", "loop closures accepted (run.json)", Better::Higher},
      {"local_maps", "", "local maps the tracker made (run.json)", Better::Lower},
  };
  return table;
}

const MetricInfo* findMetric(const std::string& name) {
  for (const auto& m : metricTable())
    if (m.name == name) return &m;
  return nullptr;
}

std::string betterName(Better b) {
  return b == Better::Higher ? "higher" : b == Better::None ? "none" : "lower";
}

Better betterOf(const std::string& name) {
  return name == "higher" ? Better::Higher : name == "none" ? Better::None : Better::Lower;
}

json scoringJson(const Scoring& s) {
  return json{{"reference", s.reference}, {"relations", s.relations}, {"log", s.log},
              {"laser", s.laser},         {"evaluate", s.evaluate}};
}

Scoring scoringFrom(const json& j) {
  Scoring s;
  s.reference = j.value("reference", "");
  s.relations = j.value("relations", "");
  s.log = j.value("log", "");
  s.laser = j.value("laser", "");
  s.evaluate = j.value("evaluate", std::vector<std::string>{});
  return s;
}

json evaluationJson(const std::vector<Evaluator>& evaluators,
                    const std::vector<CustomMetric>& custom) {
  json e = json::array(), m = json::array();
  for (const auto& x : evaluators) e.push_back({{"name", x.name}, {"command", x.command}});
  for (const auto& c : custom)
    m.push_back({{"name", c.info.name},
                 {"unit", c.info.unit},
                 {"doc", c.info.doc},
                 {"better", betterName(c.info.better)},
                 {"evaluator", c.evaluator},
                 {"key", c.key}});
  return {{"evaluators", e}, {"custom_metrics", m}};
}

void evaluationFrom(const json& j, std::vector<Evaluator>& evaluators,
                    std::vector<CustomMetric>& custom) {
  for (const auto& x : j.value("evaluators", json::array()))
    evaluators.push_back(Evaluator{x.value("name", ""), x.value("command", "")});
  for (const auto& x : j.value("custom_metrics", json::array())) {
    CustomMetric c;
    c.info.name = x.value("name", "");
    c.info.unit = x.value("unit", "");
    c.info.doc = x.value("doc", "");
    c.info.better = betterOf(x.value("better", "lower"));
    c.evaluator = x.value("evaluator", "");
    c.key = x.value("key", "");
    custom.push_back(c);
  }
}

const MetricInfo* findMetric(const std::string& name, const std::vector<CustomMetric>& custom) {
  for (const auto& m : custom)
    if (m.info.name == name) return &m.info;
  return findMetric(name);
}

namespace {

// The number at `path` (splitPath's parts: keys, and "[i]" into a list), if there is one.
std::optional<double> number(const json& j, const std::vector<std::string>& path) {
  const json* at = &j;
  for (const auto& key : path) {
    if (key.size() > 2 && key.front() == '[') {
      size_t i = 0;
      try {
        i = std::stoul(key.substr(1, key.size() - 2));
      } catch (const std::out_of_range&) {
        return std::nullopt;  // past the end of any list
      }
      if (!at->is_array() || i >= at->size()) return std::nullopt;
      at = &(*at)[i];
      continue;
    }
    if (!at->is_object() || !at->contains(key)) return std::nullopt;
    at = &(*at)[key];
  }
  if (!at->is_number()) return std::nullopt;
  return at->get<double>();
}
std::optional<double> number(const json& j, std::initializer_list<const char*> path) {
  return number(j, std::vector<std::string>(path.begin(), path.end()));
}

json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) return json();
  try {
    return json::parse(in);
  } catch (const json::exception&) {
    return json();
  }
}

// Runs `plugslam eval ...` into a JSON file; the parsed result, or the reason there is none.
struct Eval {
  json result;
  std::string error;
};

Eval evaluate(const std::string& self, std::vector<std::string> args, const std::string& out,
              const std::string& log, const std::string& cwd) {
  std::vector<std::string> argv{self, "-q", "eval"};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.insert(argv.end(), {"--format", "json", "-o", out});
  boost::system::error_code ec;
  fs::remove(out, ec);
  const ProcessResult p = runProcess(argv, cwd, log, 0);
  Eval e;
  if (!p.error.empty()) {
    e.error = p.error;
    return e;
  }
  if (p.exit_code != 0) {
    const auto tail = tailLines(log, 1);
    e.error = fmt::format("plugslam eval {} failed (exit {}){}", args[0], p.exit_code,
                          tail.empty() ? "" : ": " + tail.back());
    return e;
  }
  e.result = readJson(out);
  if (e.result.is_null()) e.error = "plugslam eval " + args[0] + " wrote no result";
  return e;
}

// Runs an evaluator's command line (placeholders replaced by shell-quoted paths) with its standard
// output into `out`; the parsed output, or why there is none.
Eval evaluateCommand(const Evaluator& e, const std::map<std::string, std::string>& places,
                     const std::string& out, const std::string& log, const std::string& cwd) {
  std::string line;
  for (size_t i = 0; i < e.command.size();) {
    const size_t close = e.command[i] == '{' ? e.command.find('}', i) : std::string::npos;
    const auto it =
        close == std::string::npos ? places.end() : places.find(e.command.substr(i + 1, close - i - 1));
    if (it == places.end()) {
      line += e.command[i++];
      continue;
    }
    line += shellQuote(it->second);
    i = close + 1;
  }
  boost::system::error_code ec;
  fs::remove(out, ec);
  const ProcessResult p =
      runProcess({"/bin/sh", "-c", "{ " + line + "\n} > " + shellQuote(out)}, cwd, log, 0);
  Eval r;
  if (!p.error.empty()) {
    r.error = p.error;
  } else if (p.exit_code != 0) {
    const auto tail = tailLines(log, 1);
    r.error = fmt::format("evaluator '{}' failed (exit {}){}", e.name, p.exit_code,
                          tail.empty() ? "" : ": " + tail.back());
  } else {
    r.result = readJson(out);
    if (r.result.is_null()) r.error = "evaluator '" + e.name + "' printed no JSON";
  }
  return r;
}

}  // namespace

MetricValues measure(const std::vector<std::string>& names, const Scoring& scoring,
                     const RunFacts& run, const std::string& self, const std::string& work_dir,
                     const std::string& source_path, const std::vector<Evaluator>& evaluators,
                     const std::vector<CustomMetric>& custom) {
  MetricValues m;
  const json report = readJson(run.out_dir + "/run.json");
  const std::string trajectory = run.out_dir + "/trajectory.tum";
  const std::string own_reference = run.out_dir + "/reference.tum";
  const std::string log = work_dir + "/eval.log";
  const auto set = [&](const std::string& name, std::optional<double> v, const std::string& why) {
    m.values[name] = v;
    if (!v) m.errors[name] = why;
  };
  // Each evaluation runs once for the metrics it gives.
  std::optional<Eval> crisp, crisp_ref, relations;
  const std::string reference =
      !scoring.reference.empty() ? scoring.reference
      : fs::exists(own_reference) ? own_reference
                                  : std::string();
  // Crispness of `trajectory` on the dataset's log, into `file`.
  const auto crispness = [&](const std::string& poses, const std::string& file) {
    const std::string input = !scoring.log.empty() ? scoring.log : source_path;
    if (input.empty()) return Eval{json(), "the dataset names no log and sets no source.path"};
    if (poses.empty())
      return Eval{json(), "the dataset names no reference and the run wrote no reference.tum"};
    std::vector<std::string> args{"crispness", input, poses};
    if (!scoring.laser.empty()) args.insert(args.end(), {"--laser", scoring.laser});
    return evaluate(self, args, work_dir + "/" + file, log, run.cwd);
  };
  // A crispness over no matched point measures nothing.
  const auto crispOf = [](const Eval& e, const std::string& key) -> std::pair<std::optional<double>, std::string> {
    if (!e.error.empty()) return {std::nullopt, e.error};
    if (key == "mean_m" && number(e.result, {"matched_points"}).value_or(0) == 0)
      return {std::nullopt, "no scan point has a neighbour in a scan far enough apart"};
    return {number(e.result, {key.c_str()}), "crispness wrote no '" + key + "'"};
  };
  std::map<std::string, Eval> evaluated;  // per evaluator, run once
  const std::map<std::string, std::string> places{{"out", run.out_dir},
                                                  {"trajectory", trajectory},
                                                  {"reference", reference},
                                                  {"source", source_path},
                                                  {"case", work_dir}};
  for (const auto& name : names) {
    const auto own = std::find_if(custom.begin(), custom.end(),
                                  [&](const CustomMetric& c) { return c.info.name == name; });
    if (own != custom.end()) {
      const auto e = std::find_if(evaluators.begin(), evaluators.end(),
                                  [&](const Evaluator& x) { return x.name == own->evaluator; });
      if (e == evaluators.end()) {
        set(name, std::nullopt, "no evaluator '" + own->evaluator + "'");
        continue;
      }
      if (!scoring.evaluate.empty() &&
          std::find(scoring.evaluate.begin(), scoring.evaluate.end(), e->name) ==
              scoring.evaluate.end()) {
        set(name, std::nullopt, "the dataset's `evaluate` does not run '" + e->name + "'");
        continue;
      }
      if (!evaluated.count(e->name))
        evaluated[e->name] = evaluateCommand(*e, places, work_dir + "/" + e->name + ".json",
                                             log, run.cwd);
      const Eval& got = evaluated[e->name];
      set(name, number(got.result, splitPath(own->key)),
          got.error.empty() ? "evaluator '" + e->name + "' gave no number at '" + own->key + "'"
                            : got.error);
      continue;
    }
    if (name == "ate" || name == "rpe") {
      if (!scoring.reference.empty()) {
        std::vector<std::string> args{name, scoring.reference, trajectory};
        if (name == "rpe") args.insert(args.end(), {"--unit", "m", "--delta", "1"});
        const Eval e = evaluate(self, args, work_dir + "/" + name + ".json", log, run.cwd);
        set(name, number(e.result, {"translation_m", "rmse"}), e.error);
      } else {
        set(name, number(report, {"reference", name == "ate" ? "ate_rmse_m" : "rpe_1m_rmse_m"}),
            "the dataset names no reference and the run scored none (run.json has no "
            "'reference')");
      }
    } else if (name == "relations" || name == "relations_deg" || name == "relations_unused") {
      if (!relations) {
        std::vector<std::string> args{"relations", trajectory};
        if (!scoring.relations.empty())
          args.insert(args.end(), {"--relations", scoring.relations});
        else if (!reference.empty())
          args.insert(args.end(), {"--reference", reference});
        if (args.size() == 2)
          relations = Eval{json(), "no relations file, no reference, and the run wrote no "
                                   "reference.tum"};
        else
          relations = evaluate(self, args, work_dir + "/relations.json", log, run.cwd);
      }
      if (name == "relations_unused") {
        const auto all = number(relations->result, {"relations"});
        const auto used = number(relations->result, {"used"});
        set(name, all && used ? std::optional<double>(*all - *used) : std::nullopt,
            relations->error.empty() ? "eval relations wrote no counts" : relations->error);
      } else {
        set(name,
            number(relations->result,
                   {name == "relations" ? "translation_m" : "rotation_deg", "mean"}),
            relations->error);
      }
    } else if (name == "crispness" || name == "coverage") {
      if (!crisp) crisp = crispness(trajectory, "crispness.json");
      const auto [v, why] = crispOf(*crisp, name == "crispness" ? "mean_m" : "coverage");
      set(name, v, why);
    } else if (name == "crispness_ref" || name == "coverage_ref") {
      if (!crisp_ref) crisp_ref = crispness(reference, "crispness_ref.json");
      const auto [v, why] = crispOf(*crisp_ref, name == "crispness_ref" ? "mean_m" : "coverage");
      set(name, v, why);
    } else if (name == "hz") {
      set(name, number(report, {"hz"}), "run.json has no 'hz'");
    } else if (name == "pipeline_hz") {
      set(name, number(report, {"pipeline_hz"}), "run.json has no 'pipeline_hz'");
    } else if (name == "memory") {
      set(name, run.peak_rss_mib, "");
    } else if (name == "time") {
      set(name, run.wall_s, "");
    } else if (name == "tracking_failures") {
      set(name, number(report, {"tracking_failures"}), "run.json has no 'tracking_failures'");
    } else if (name == "components") {
      const json* c = report.is_object() && report.contains("graph") && report["graph"].is_object()
                          ? &report["graph"]
                          : nullptr;
      const bool has = c && c->contains("components") && (*c)["components"].is_array();
      set(name, has ? std::optional<double>((*c)["components"].size()) : std::nullopt,
          "run.json has no graph components");
    } else if (name == "ambiguous") {
      set(name, number(report, {"tracking_ambiguous"}), "run.json has no 'tracking_ambiguous'");
    } else if (name == "search_s" || name == "refine_s" || name == "merge_s") {
      const std::string key = name.substr(0, name.size() - 2);
      set(name, number(report, {"tracking_time_s", key.c_str()}),
          "run.json has no 'tracking_time_s'");
    } else if (name == "local_maps") {
      set(name, number(report, {"local_maps"}), "run.json has no 'local_maps'");
    } else if (name == "loops") {
      set(name, number(report, {"graph", "loops_accepted"}), "the run has no graph");
    }
  }
  return m;
}

}  // namespace plugslam::runtime::sweep
