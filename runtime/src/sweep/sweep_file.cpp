#include "sweep/sweep_file.h"

#include <fmt/format.h>

#include <boost/filesystem.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include "build_paths.h"
#include "config_builder.h"
#include "plugslam/errors.h"
#include "plugslam/registry.h"
#include "plugslam/yaml_load.h"
#include "sweep/metrics.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;

namespace {

const std::vector<std::string> kTopKeys{"config",  "datasets", "set",     "grid",
                                        "zip",     "repeat",   "metrics", "evaluators",
                                        "timeout", "slurm",    "hosts",   "title",
                                        "notes",   "targets"};
const std::vector<std::string> kEvaluatorKeys{"command", "metrics"};
const std::vector<std::string> kCustomMetricKeys{"key", "unit", "better", "doc"};
const std::vector<std::string> kDatasetKeys{"set", "reference", "relations", "log", "laser",
                                            "config", "evaluate"};
const std::vector<std::string> kSlurmKeys{"partition", "time",         "mem",  "account",
                                          "cpus",      "max_parallel", "extra"};

Origin originOf(const YAML::Node& node) {
  const auto m = node.Mark();
  return m.line >= 0 ? Origin{m.line + 1, m.column + 1} : Origin{};
}

// A value as `--set` takes it: scalars as written (0.5 stays 0.5), anything else in flow style.
std::string valueText(const YAML::Node& node) {
  if (node.IsScalar()) return node.Scalar();
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

class Reader {
 public:
  explicit Reader(std::string name) : name_(std::move(name)) {}

  void error(const YAML::Node& at, const std::string& key, const std::string& message) {
    const Origin o = originOf(at);
    errors_.emplace_back(name_, o.line, o.column, key, message);
  }
  void throwIfAny() {
    // In file order, as a config's errors are, whatever order the checks ran in.
    std::stable_sort(errors_.begin(), errors_.end(), [](const ConfigError& a, const ConfigError& b) {
      return std::make_pair(a.line(), a.column()) < std::make_pair(b.line(), b.column());
    });
    if (errors_.size() == 1) throw errors_[0];
    if (!errors_.empty()) throw ConfigErrorList(errors_);
  }

  // Reports keys of `map` that are not in `known` (with a near match), returns false if any.
  bool knownKeys(const YAML::Node& map, const std::vector<std::string>& known,
                 const std::string& where) {
    bool ok = true;
    for (auto it = map.begin(); it != map.end(); ++it) {
      const std::string key = it->first.as<std::string>("");
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      std::string msg = "unknown key '" + key + "'" + (where.empty() ? "" : " in " + where);
      const std::string near = closestMatch(key, known);
      if (!near.empty()) msg += "; did you mean '" + near + "'?";
      else {
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        msg += " (known: " + list + ")";
      }
      error(it->first, key, msg);
      ok = false;
    }
    return ok;
  }

  bool scalar(const YAML::Node& node, const std::string& key, std::string& out) {
    if (!node.IsScalar()) {
      error(node, key, "expected a single value");
      return false;
    }
    out = node.Scalar();
    return true;
  }

  template <typename T>
  bool number(const YAML::Node& node, const std::string& key, T& out, T min) {
    try {
      out = node.as<T>();
    } catch (const YAML::Exception&) {
      error(node, key, "expected a number, got '" + valueText(node) + "'");
      return false;
    }
    if (out < min) {
      error(node, key, fmt::format("must be at least {}", min));
      return false;
    }
    return true;
  }

  // A key of `--set` form; its syntax is checked now, its meaning when the configs are built.
  bool overrideKey(const YAML::Node& key_node, const std::string& key) {
    try {
      const auto parts = splitPath(key);
      if (!parts.empty() && parts[0] == "base") {
        error(key_node, key, "a config's base cannot be swept: list the configs under 'config'");
        return false;
      }
    } catch (const InputError& e) {
      error(key_node, key, e.what());
      return false;
    }
    return true;
  }

  std::vector<Override> overrides(const YAML::Node& map, const std::string& where) {
    std::vector<Override> out;
    if (!map.IsMap()) {
      error(map, where, "expected a map of parameter: value (as --set takes them)");
      return out;
    }
    for (auto it = map.begin(); it != map.end(); ++it) {
      const std::string key = it->first.as<std::string>("");
      if (!overrideKey(it->first, key)) continue;
      // null, as `--set KEY=null`: the slot or parameter is unset (a motion model removed).
      if (!it->second.IsDefined() || it->second.IsNull()) {
        out.push_back({key, "null", originOf(it->first)});
        continue;
      }
      out.push_back({key, valueText(it->second), originOf(it->first)});
    }
    return out;
  }

  std::vector<std::string> strings(const YAML::Node& node, const std::string& key) {
    std::vector<std::string> out;
    if (node.IsScalar()) {
      out.push_back(node.Scalar());
    } else if (node.IsSequence()) {
      for (const auto& item : node) {
        std::string s;
        if (scalar(item, key, s)) out.push_back(s);
      }
    } else {
      error(node, key, "expected a value or a list of values");
    }
    return out;
  }

  std::string name_;
  std::vector<ConfigError> errors_;
};

std::string findConfig(const std::string& written, const std::string& sweep_file) {
  const fs::path p(written);
  if (p.is_absolute()) return fs::exists(p) ? p.string() : "";
  std::vector<fs::path> places;
  const fs::path dir = fs::path(sweep_file).parent_path();
  if (!sweep_file.empty() && sweep_file[0] != '<') places.push_back(dir / p);
  places.push_back(p);
  // "configs/x.yaml" also names a shipped config wherever the sweep file is.
  for (const fs::path& root :
       {fs::path(build_paths::installDataDir()), fs::path(build_paths::sourceDir())})
    places.push_back(root / p);
  for (const auto& candidate : places)
    if (fs::is_regular_file(candidate)) return fs::absolute(candidate).lexically_normal().string();
  return "";
}

}  // namespace

SweepFile parseSweep(const std::string& text, const std::string& name) {
  Reader r(name);
  YAML::Node root;
  try {
    root = loadYaml(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw ConfigError(name, 1, 1, "", "a sweep file is a map (`plugslam describe sweep`)");
  SweepFile s;
  s.file = name;
  r.knownKeys(root, kTopKeys, "");

  // config: the file's list, then each dataset's own (one entry per distinct file)
  const auto addConfig = [&](const YAML::Node& item, const std::string& key,
                             bool shared) -> std::optional<size_t> {
    std::string written;
    if (!r.scalar(item, key, written)) return std::nullopt;
    const std::string found = findConfig(written, name);
    if (found.empty()) {
      r.error(item, key, "no config file '" + written + "' (looked beside the sweep file, in the current folder and among the shipped configs)");
      return std::nullopt;
    }
    const auto at = std::find(s.configs.begin(), s.configs.end(), found);
    if (at != s.configs.end()) {
      if (shared) r.error(item, key, "'" + written + "' is listed twice");
      return shared ? std::nullopt : std::optional<size_t>(at - s.configs.begin());
    }
    s.configs.push_back(found);
    s.config_origins.push_back(originOf(item));
    return s.configs.size() - 1;
  };
  const auto items = [](const YAML::Node& list) {
    std::vector<YAML::Node> out;
    if (list.IsSequence())
      for (const auto& item : list) out.push_back(item);
    else
      out.push_back(list);
    return out;
  };
  if (const YAML::Node list = root["config"]) {
    const auto listed = items(list);
    if (listed.empty()) r.error(list, "config", "lists no config");
    for (const auto& item : listed) addConfig(item, "config", true);
  }
  s.shared_configs = s.configs.size();

  // set
  if (root["set"]) s.set = r.overrides(root["set"], "set");

  // datasets
  std::vector<std::pair<YAML::Node, std::string>> evaluate_nodes;  // checked once evaluators are read
  if (const YAML::Node ds = root["datasets"]) {
    if (!ds.IsMap() || ds.size() == 0) {
      r.error(ds, "datasets", "expected a map: name -> overrides (or {set: ..., reference: ...})");
    } else {
      for (auto it = ds.begin(); it != ds.end(); ++it) {
        Dataset d;
        d.name = it->first.as<std::string>("");
        d.origin = originOf(it->first);
        const std::string where = "datasets." + d.name;
        if (d.name.empty() || d.name.find_first_of("/\\ \t,|") != std::string::npos) {
          r.error(it->first, where, "a dataset name is one word (no spaces, '/', ',' or '|')");
          continue;
        }
        const YAML::Node body = it->second;
        if (body.IsMap() && body["set"]) {
          // The long form: overrides under `set`, beside what the results are scored against.
          r.knownKeys(body, kDatasetKeys, where);
          d.set = r.overrides(body["set"], where + ".set");
          std::string* fields[] = {&d.scoring.reference, &d.scoring.relations, &d.scoring.log,
                                   &d.scoring.laser};
          // A dataset that only one kind of pipeline can read (a camera's) names its configs.
          if (const YAML::Node own = body["config"]) {
            const auto listed = items(own);
            if (listed.empty()) r.error(own, where + ".config", "lists no config");
            for (const auto& item : listed)
              if (const auto c = addConfig(item, where + ".config", false))
                if (std::find(d.configs.begin(), d.configs.end(), *c) == d.configs.end())
                  d.configs.push_back(*c);
          }
          if (const YAML::Node only = body["evaluate"]) {
            for (const auto& item : items(only)) {
              std::string e;
              if (r.scalar(item, where + ".evaluate", e)) d.scoring.evaluate.push_back(e);
            }
            evaluate_nodes.emplace_back(only, where + ".evaluate");
          }
          for (size_t k = 1; k <= 4; ++k) {
            YAML::Node field = body[kDatasetKeys[k]];
            if (!field) continue;
            // Scoring files are read here, so ${PLUGSLAM_DATA} is expanded here; overrides reach
            // the runs as written and each run expands them on the machine it runs on.
            try {
              expandVariables(field, name);
            } catch (const ConfigError& e) {
              r.error(field, where + "." + kDatasetKeys[k], e.message());
              continue;
            }
            r.scalar(field, where + "." + kDatasetKeys[k], *fields[k - 1]);
          }
        } else if (body.IsMap()) {
          for (const auto& key : kDatasetKeys)
            if (key != "set" && body[key])
              r.error(body[key], where + "." + key,
                      "'" + key + "' belongs with the long form: write the overrides under 'set:'");
          d.set = r.overrides(body, where);
        } else if (!body.IsNull()) {
          r.error(body, where, "expected a map of overrides, e.g. {source.path: log.gz}");
          continue;
        }
        s.datasets.push_back(std::move(d));
      }
    }
  }
  if (s.datasets.empty()) {
    Dataset all;
    all.name = "default";
    s.datasets.push_back(all);
  }
  for (size_t c = 0; c < s.shared_configs; ++c)
    if (std::none_of(s.datasets.begin(), s.datasets.end(),
                     [&](const Dataset& d) { return s.runs(c, d); }))
      r.error(root["config"], "config",
              "'" + fs::path(s.configs[c]).filename().string() +
                  "' runs on no dataset: every dataset names its own configs");
  if (!root["config"] && std::any_of(s.datasets.begin(), s.datasets.end(),
                                     [](const Dataset& d) { return d.configs.empty(); }))
    r.error(root, "config",
            "missing key 'config': the pipeline config(s) to run (or a `config` in every dataset)");

  // grid and zip
  std::map<std::string, Origin> swept;
  const auto addKey = [&](const YAML::Node& key_node, const std::string& key, Axis& axis) {
    if (!r.overrideKey(key_node, key)) return false;
    if (swept.count(key)) {
      r.error(key_node, key, fmt::format("'{}' is swept twice (also at line {})", key, swept[key].line));
      return false;
    }
    swept[key] = originOf(key_node);
    axis.keys.push_back(key);
    axis.origins.push_back(originOf(key_node));
    return true;
  };
  const auto valueList = [&](const YAML::Node& node, const std::string& key) {
    std::vector<std::string> out;
    if (!node.IsSequence() || node.size() == 0) {
      r.error(node, key, "expected a non-empty list of values");
      return out;
    }
    std::set<std::string> seen;
    for (const auto& v : node) {
      if (v.IsNull()) {
        r.error(v, key, "an empty value");
        continue;
      }
      if (!seen.insert(valueText(v)).second) {
        r.error(v, key, "value '" + valueText(v) + "' is listed twice");
        continue;
      }
      out.push_back(valueText(v));
    }
    return out;
  };
  if (const YAML::Node grid = root["grid"]) {
    if (!grid.IsMap()) r.error(grid, "grid", "expected a map: parameter -> list of values");
    else
      for (auto it = grid.begin(); it != grid.end(); ++it) {
        Axis axis;
        const std::string key = it->first.as<std::string>("");
        if (!addKey(it->first, key, axis)) continue;
        for (auto& v : valueList(it->second, key)) axis.values.push_back({v});
        if (!axis.values.empty()) s.axes.push_back(std::move(axis));
      }
  }
  if (const YAML::Node zip = root["zip"]) {
    std::vector<YAML::Node> groups;
    if (zip.IsMap()) groups.push_back(zip);
    else if (zip.IsSequence())
      for (const auto& g : zip) groups.push_back(g);
    if (groups.empty()) r.error(zip, "zip", "expected a map (or a list of maps): parameter -> list of values, lists of one length");
    for (const auto& g : groups) {
      if (!g.IsMap() || g.size() == 0) {
        r.error(g, "zip", "expected a map: parameter -> list of values");
        continue;
      }
      Axis axis;
      size_t length = 0;
      bool ok = true;
      for (auto it = g.begin(); it != g.end(); ++it) {
        const std::string key = it->first.as<std::string>("");
        if (!addKey(it->first, key, axis)) {
          ok = false;
          continue;
        }
        auto values = valueList(it->second, key);
        if (axis.keys.size() == 1) length = values.size();
        if (values.size() != length) {
          r.error(it->second, key,
                  fmt::format("has {} values, the zip's first key {}: zipped values go together", values.size(), length));
          ok = false;
          continue;
        }
        if (axis.values.empty()) axis.values.resize(length);
        for (size_t i = 0; i < length; ++i) axis.values[i].push_back(values[i]);
      }
      if (ok && length > 0) s.axes.push_back(std::move(axis));
    }
  }
  const auto clash = [&](const std::vector<Override>& set, const std::string& where) {
    for (const auto& o : set)
      if (swept.count(o.key)) {
        r.errors_.emplace_back(name, o.origin.line, o.origin.column, o.key,
                               fmt::format("'{}' is also swept (line {}): {} cannot fix it", o.key, swept[o.key].line, where));
      }
  };
  clash(s.set, "'set'");
  for (const auto& d : s.datasets) clash(d.set, "dataset '" + d.name + "'");

  if (const YAML::Node n = root["repeat"]) r.number(n, "repeat", s.repeat, 1);
  if (const YAML::Node n = root["timeout"]) r.number(n, "timeout", s.timeout_s, 0.0);
  if (const YAML::Node n = root["title"]) r.scalar(n, "title", s.title);
  if (const YAML::Node n = root["notes"]) r.scalar(n, "notes", s.notes);

  // evaluators: the file's own evaluations, and the metrics they give
  if (const YAML::Node ev = root["evaluators"]) {
    if (!ev.IsMap()) r.error(ev, "evaluators", "expected a map: NAME -> {command: ..., metrics: ...}");
    for (auto it = ev.begin(); ev.IsMap() && it != ev.end(); ++it) {
      Evaluator e;
      e.name = it->first.as<std::string>("");
      const std::string where = "evaluators." + e.name;
      const YAML::Node body = it->second;
      if (!body.IsMap()) {
        r.error(body, where, "expected {command: \"...\", metrics: {NAME: {key: ...}}}");
        continue;
      }
      r.knownKeys(body, kEvaluatorKeys, where);
      if (!body["command"] || !r.scalar(body["command"], where + ".command", e.command)) {
        if (!body["command"]) r.error(body, where, "missing key 'command': the command line to run");
        continue;
      }
      const YAML::Node ms = body["metrics"];
      if (!ms || !ms.IsMap() || ms.size() == 0) {
        r.error(ms ? ms : body, where + ".metrics", "expected a map: METRIC -> {key: PATH, ...}");
        continue;
      }
      for (auto m = ms.begin(); m != ms.end(); ++m) {
        CustomMetric c;
        c.evaluator = e.name;
        c.info.name = m->first.as<std::string>("");
        const std::string at = where + ".metrics." + c.info.name;
        if (findMetric(c.info.name, s.custom_metrics)) {
          r.error(m->first, at, "'" + c.info.name + "' is already a metric: name it otherwise");
          continue;
        }
        const YAML::Node spec = m->second;
        if (!spec.IsMap() || !spec["key"]) {
          r.error(spec, at,
                  "expected {key: PATH (dots into the output, [i] into a list), unit, better, "
                  "doc}");
          continue;
        }
        r.knownKeys(spec, kCustomMetricKeys, at);
        // The path is read as `--set` reads its paths ("a.b[2].c"), checked now.
        if (r.scalar(spec["key"], at + ".key", c.key)) {
          try {
            splitPath(c.key);
          } catch (const InputError& e) {
            r.error(spec["key"], at + ".key", e.what());
          }
        }
        c.info.doc = "'" + c.key + "' of evaluator " + e.name;  // unless `doc` says more
        if (spec["unit"]) r.scalar(spec["unit"], at + ".unit", c.info.unit);
        if (spec["doc"]) r.scalar(spec["doc"], at + ".doc", c.info.doc);
        std::string better = "lower";
        if (spec["better"] && r.scalar(spec["better"], at + ".better", better) &&
            better != "lower" && better != "higher" && better != "none")
          r.error(spec["better"], at + ".better",
                  "expected 'lower', 'higher' or 'none', got '" + better + "'");
        c.info.better = betterOf(better);
        s.custom_metrics.push_back(c);
      }
      s.evaluators.push_back(e);
    }
  }

  for (const auto& [node, where] : evaluate_nodes)
    for (const auto& item : items(node)) {
      const std::string e = item.as<std::string>("");
      if (std::none_of(s.evaluators.begin(), s.evaluators.end(),
                       [&](const Evaluator& x) { return x.name == e; }))
        r.error(item, where, "no evaluator '" + e + "' in `evaluators`");
    }

  if (const YAML::Node m = root["metrics"]) {
    std::vector<std::string> names;
    for (const auto& item : m.IsSequence() ? m : YAML::Node(YAML::NodeType::Sequence)) {
      std::string metric;
      if (!r.scalar(item, "metrics", metric)) continue;
      if (!findMetric(metric, s.custom_metrics)) {
        std::vector<std::string> known;
        for (const auto& info : metricTable()) known.push_back(info.name);
        for (const auto& c : s.custom_metrics) known.push_back(c.info.name);
        std::string msg = "unknown metric '" + metric + "'";
        const std::string near = closestMatch(metric, known);
        if (!near.empty()) msg += "; did you mean '" + near + "'?";
        std::string list;
        for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
        r.error(item, "metrics", msg + " (known: " + list + ")");
        continue;
      }
      if (std::find(s.metrics.begin(), s.metrics.end(), metric) != s.metrics.end()) {
        r.error(item, "metrics", "'" + metric + "' is listed twice");
        continue;
      }
      s.metrics.push_back(metric);
    }
    if (!m.IsSequence()) r.error(m, "metrics", "expected a list of metric names, e.g. [ate, hz]");
  } else {
    s.metrics = {"hz"};
  }

  if (const YAML::Node t = root["targets"]) {
    const auto measured = [&s](const std::string& metric) {
      return std::find(s.metrics.begin(), s.metrics.end(), metric) != s.metrics.end();
    };
    if (!t.IsMap()) {
      r.error(t, "targets", "expected a map: METRIC -> \"<= VALUE\" or \">= VALUE\"");
    } else {
      for (const auto& kv : t) {
        Target target;
        target.metric = kv.first.as<std::string>();
        std::string condition;
        if (!r.scalar(kv.second, "targets", condition)) continue;
        if (!measured(target.metric)) {
          r.error(kv.first, "targets",
                  "'" + target.metric + "' is not among the sweep's metrics: list it in `metrics`");
          continue;
        }
        // "<= NUMBER", or "<= [FACTOR *] METRIC".
        const auto start = condition.find_first_not_of(' ');
        const std::string op = start == std::string::npos ? "" : condition.substr(start, 2);
        bool ok = op == "<=" || op == ">=";
        if (ok) {
          target.at_most = op == "<=";
          std::string rest = condition.substr(start + 2);
          const auto trim = [](std::string v) {
            const auto a = v.find_first_not_of(' '), b = v.find_last_not_of(' ');
            return a == std::string::npos ? std::string() : v.substr(a, b - a + 1);
          };
          const auto star = rest.find('*');
          if (star != std::string::npos) {
            target.of = trim(rest.substr(star + 1));
            rest = rest.substr(0, star);
          } else if (findMetric(trim(rest), s.custom_metrics)) {
            target.of = trim(rest);
            rest = "1";
          }
          try {
            size_t used = 0;
            target.value = std::stod(rest, &used);
            ok = rest.find_first_not_of(' ', used) == std::string::npos &&
                 std::isfinite(target.value) && (star == std::string::npos || !target.of.empty());
          } catch (const std::exception&) {
            ok = false;
          }
          if (ok && !target.of.empty() && !measured(target.of)) {
            r.error(kv.second, "targets",
                    "'" + target.of + "' (in the target of '" + target.metric +
                        "') is not among the sweep's metrics: list it in `metrics`");
            continue;
          }
        }
        if (!ok) {
          r.error(kv.second, "targets",
                  "expected \"<= VALUE\", \">= VALUE\" or \"<= [FACTOR *] METRIC\" for '" +
                      target.metric + "', got '" + condition + "'");
          continue;
        }
        s.targets.push_back(target);
      }
    }
  }

  if (const YAML::Node sl = root["slurm"]) {
    if (!sl.IsMap()) r.error(sl, "slurm", "expected a map: partition, time, mem, ...");
    else {
      r.knownKeys(sl, kSlurmKeys, "slurm");
      if (sl["partition"]) r.scalar(sl["partition"], "slurm.partition", s.slurm.partition);
      if (sl["time"]) r.scalar(sl["time"], "slurm.time", s.slurm.time);
      if (sl["mem"]) r.scalar(sl["mem"], "slurm.mem", s.slurm.mem);
      if (sl["account"]) r.scalar(sl["account"], "slurm.account", s.slurm.account);
      if (sl["cpus"]) r.number(sl["cpus"], "slurm.cpus", s.slurm.cpus, 1);
      if (sl["max_parallel"]) r.number(sl["max_parallel"], "slurm.max_parallel", s.slurm.max_parallel, 1);
      if (sl["extra"]) s.slurm.extra = r.strings(sl["extra"], "slurm.extra");
    }
  }
  if (const YAML::Node h = root["hosts"]) s.hosts = r.strings(h, "hosts");

  r.throwIfAny();
  return s;
}

SweepFile readSweepFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read sweep file '" + path + "'");
  std::stringstream text;
  text << in.rdbuf();
  return parseSweep(text.str(), path);
}

bool SweepFile::runs(size_t config, const Dataset& d) const {
  if (d.configs.empty()) return config < shared_configs;
  return std::find(d.configs.begin(), d.configs.end(), config) != d.configs.end();
}

std::string Target::text() const {
  const std::string bound = of.empty()   ? fmt::format("{}", value)
                            : value == 1 ? of
                                         : fmt::format("{} * {}", value, of);
  return fmt::format("{} {} {}", metric, at_most ? "<=" : ">=", bound);
}

std::string describeSweepFile() {
  std::string metrics;
  for (const auto& m : metricTable())
    metrics += fmt::format("      {:<18} {}{} ({} is better)\n", m.name, m.doc,
                           m.unit.empty() ? "" : " [" + m.unit + "]",
                           betterName(m.better));
  return "sweep (the keys of a sweep file: `plugslam sweep plan|run FILE`)\n"
         "  Runs configs on datasets over a parameter grid; each case is `plugslam run` with\n"
         "  --set overrides, and its id is a hash of what it runs, so a finished case is never\n"
         "  run again. Relative paths in values are relative to the folder the sweep runs in.\n\n"
         "keys:\n"
         "  config     path or list of paths (required)\n"
         "      pipeline configs; a relative path is looked up beside the sweep file, in the\n"
         "      current folder, then among the shipped configs\n"
         "  datasets   map: name -> {PARAMETER: VALUE, ...}\n"
         "      the inputs, each a set of overrides (typically source.path); the long form\n"
         "      {set: {...}, reference: FILE, relations: FILE, log: FILE, laser: NAME} also names\n"
         "      what the results are scored against (default: what the run itself wrote), and\n"
         "      config: FILE or [FILES] runs it with those configs only (not the file's `config`,\n"
         "      which may then be left out), evaluate: [NAMES] runs only those `evaluators` on it\n"
         "  set        map: PARAMETER -> VALUE, applied to every case\n"
         "  grid       map: PARAMETER -> [VALUES]; the cases are the full product\n"
         "  zip        map (or list of maps): PARAMETER -> [VALUES], lists of one length whose\n"
         "      i-th values go together; one axis of the product\n"
         "  repeat     runs per case (default 1); the report gives median, min and max\n"
         "  metrics    list, measured on each result (default [hz]):\n" +
         metrics +
         "  evaluators map: NAME -> {command: LINE, metrics: {METRIC: {key: PATH, unit: U,\n"
         "      better: lower|higher|none, doc: TEXT}}}: a shell command run on each finished run\n"
         "      whose standard output is JSON, and the metrics it gives (the number at PATH, dots\n"
         "      into the output), to list in `metrics` like the others; in LINE {out},\n"
         "      {trajectory}, {reference}, {source} and {case} are the run's folder, its\n"
         "      trajectory.tum, the dataset's reference (else the run's reference.tum), its\n"
         "      source.path and the case's folder; it runs where the sweep runs\n"
         "  timeout    seconds a run may take (default 0: no limit); a run past it is stopped and\n"
         "      recorded as timed out\n"
         "  slurm      map: partition, time, mem, account, cpus, max_parallel, extra (list of\n"
         "      sbatch arguments); the flags of `sweep run --engine slurm` win\n"
         "  hosts      list of ssh logins for `--engine parallel` (or --hosts)\n"
         "  title      the heading of the report's section (`sweep report --section`)\n"
         "  notes      text above the section's table: what is run and what the cells mean\n"
         "  targets    map: METRIC -> \"<= VALUE\" or \">= VALUE\"; the report says of each grid\n"
         "      point whether every run meets them all (a metric of `metrics`). VALUE may be\n"
         "      [FACTOR *] METRIC, e.g. \">= 0.9 * coverage_ref\": a multiple of another metric of\n"
         "      the same run; where that one has no value the target is not judged, and said so\n";
}

}  // namespace plugslam::runtime::sweep
