#include "sweep/plan.h"

#include <fmt/format.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <boost/filesystem.hpp>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "run_config.h"
#include "sweep/case_id.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;
using nlohmann::json;

namespace {

// The config's text as a run of it reads it, with the data folder written as the variable again:
// the same config gives the same ids on every machine, wherever that machine keeps its data.
std::string configText(const std::string& path) {
  std::string text = resolvedYaml(loadConfigFile(path));
  const std::string data = dataFolder();
  if (!data.empty())
    for (size_t at = text.find(data); at != std::string::npos; at = text.find(data, at))
      text.replace(at, data.size(), "${PLUGSLAM_DATA}");
  return text;
}

std::vector<std::string> configLabels(const std::vector<std::string>& configs) {
  std::vector<std::string> labels;
  std::map<std::string, int> stems;
  for (const auto& c : configs) ++stems[fs::path(c).stem().string()];
  for (const auto& c : configs) {
    const fs::path p(c);
    labels.push_back(stems[p.stem().string()] > 1
                         ? (p.parent_path().filename() / p.stem()).string()
                         : p.stem().string());
  }
  return labels;
}

// Plan files are written in place, without a temporary file or fsync: a plan of 10,000 cases
// must take seconds, and a case file cut by a crash belongs to a case without a result, which
// the next `plan` or `run` writes again. Only results are written atomically.
void writeSmallFile(const std::string& path, const std::string& content) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError("cannot write '" + path + "': " + std::strerror(errno));
  const bool written = ::write(fd, content.data(), content.size()) == static_cast<ssize_t>(content.size());
  ::close(fd);
  if (!written) throw InputError("cannot write '" + path + "'");
}

std::string readSmallFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return "";
  std::string text;
  char buffer[8192];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<size_t>(n));
  ::close(fd);
  return text;
}

// The points of an axis whose values stand for all of them (see validateSweep), without the
// first, which every build has.
std::vector<size_t> pointsToCheck(const Axis& axis) {
  std::set<size_t> points;
  for (size_t k = 0; k < axis.keys.size(); ++k) {
    std::optional<size_t> lo, hi;
    std::set<std::string> seen;
    for (size_t i = 0; i < axis.values.size(); ++i) {
      const std::string& text = axis.values[i][k];
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (!text.empty() && end && *end == '\0') {
        if (!lo || v < std::strtod(axis.values[*lo][k].c_str(), nullptr)) lo = i;
        if (!hi || v > std::strtod(axis.values[*hi][k].c_str(), nullptr)) hi = i;
      } else if (seen.insert(text).second) {
        points.insert(i);
      }
    }
    if (lo) points.insert(*lo);
    if (hi) points.insert(*hi);
  }
  points.erase(0);
  return {points.begin(), points.end()};
}

}  // namespace

std::string Case::groupKey() const {
  std::string key = config_label + '\x1f' + dataset;
  for (const auto& [k, v] : params) key += '\x1f' + k + '=' + v;
  return key;
}

std::string shellQuote(const std::string& word) {
  if (!word.empty() && word.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789_-./=:,+@%") == std::string::npos)
    return word;
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string runsOn(const Plan& plan) {
  std::set<std::pair<std::string, std::string>> pairs;
  for (const auto& c : plan.cases) pairs.emplace(c.config_label, c.dataset);
  return pairs.size() == plan.config_labels.size() * plan.datasets.size()
             ? fmt::format("{} configs x {} datasets", plan.config_labels.size(),
                           plan.datasets.size())
             : fmt::format("{} config-dataset pairs", pairs.size());
}

Plan expandSweep(const SweepFile& sweep) {
  Plan plan;
  static_cast<SweepSettings&>(plan) = sweep;
  plan.sweep_file = sweep.file;
  plan.config_labels = configLabels(sweep.configs);
  for (const auto& d : sweep.datasets) plan.datasets.push_back(d.name);
  for (const auto& axis : sweep.axes)
    for (const auto& k : axis.keys) plan.swept_keys.push_back(k);
  size_t points = 1;
  for (const auto& axis : sweep.axes) points *= axis.values.size();
  plan.cases.reserve(sweep.configs.size() * sweep.datasets.size() * points * sweep.repeat);
  for (size_t c = 0; c < sweep.configs.size(); ++c) {
    const std::string text = configText(sweep.configs[c]);
    for (const auto& d : sweep.datasets) {
      if (!sweep.runs(c, d)) continue;
      std::vector<std::string> base;
      std::string source_path;
      for (const auto* list : {&sweep.set, &d.set})
        for (const auto& o : *list) {
          base.push_back(o.text());
          if (o.key == "source.path") source_path = o.value;
        }
      for (size_t p = 0; p < points; ++p) {
        Case proto;
        proto.config = sweep.configs[c];
        proto.config_label = plan.config_labels[c];
        proto.dataset = d.name;
        proto.overrides = base;
        proto.source_path = source_path;
        proto.scoring = d.scoring;
        // The last axis varies fastest, as nested loops written in file order would.
        size_t rest = p;
        std::vector<size_t> at(sweep.axes.size());
        for (size_t a = sweep.axes.size(); a-- > 0;) {
          at[a] = rest % sweep.axes[a].values.size();
          rest /= sweep.axes[a].values.size();
        }
        for (size_t a = 0; a < sweep.axes.size(); ++a)
          for (size_t k = 0; k < sweep.axes[a].keys.size(); ++k) {
            const auto& key = sweep.axes[a].keys[k];
            const auto& value = sweep.axes[a].values[at[a]][k];
            proto.params.emplace_back(key, value);
            proto.overrides.push_back(key + "=" + value);
            if (key == "source.path") proto.source_path = value;
          }
        for (int r = 1; r <= sweep.repeat; ++r) {
          Case one = proto;
          one.repeat = r;
          one.id = caseId(text, one.overrides, r);
          plan.cases.push_back(std::move(one));
        }
      }
    }
  }
  return plan;
}

void validateSweep(const SweepFile& sweep, PluginManager& plugins) {
  std::vector<ConfigError> errors;
  std::set<std::string> seen;  // one report per distinct message
  // Each override is applied with its place in the sweep file as its origin, so the builder's
  // errors on it point there.
  const auto origin = [&](const Origin& o) {
    return fmt::format("{}:{}:{}", sweep.file, o.line, o.column);
  };
  const auto build = [&](size_t c, const Dataset& d, const std::vector<size_t>& point,
                         const std::string& what) {
    try {
      ConfigDocument doc = loadConfigFile(sweep.configs[c]);
      for (const auto* list : {&sweep.set, &d.set})
        for (const auto& o : *list) applyOverride(doc, o.text(), origin(o.origin));
      for (size_t a = 0; a < sweep.axes.size(); ++a)
        for (size_t k = 0; k < sweep.axes[a].keys.size(); ++k)
          applyOverride(doc, sweep.axes[a].keys[k] + "=" + sweep.axes[a].values[point[a]][k],
                        origin(sweep.axes[a].origins[k]));
      buildRun(doc, plugins);
    } catch (const ConfigErrorList& list) {
      for (const auto& e : list.errors())
        if (seen.insert(e.what()).second)
          errors.emplace_back(e.file(), e.line(), e.column(), e.path(), e.message() + " (" + what + ")");
    } catch (const ConfigError& e) {
      if (seen.insert(e.what()).second)
        errors.emplace_back(e.file(), e.line(), e.column(), e.path(), e.message() + " (" + what + ")");
    } catch (const InputError& e) {
      if (seen.insert(e.what()).second)
        errors.emplace_back(sweep.file, 0, 0, "", std::string(e.what()) + " (" + what + ")");
    }
  };
  const std::vector<size_t> first(sweep.axes.size(), 0);
  const auto name = [&](size_t c) { return fs::path(sweep.configs[c]).filename().string(); };
  for (size_t c = 0; c < sweep.configs.size(); ++c) {
    const Dataset* runs = nullptr;  // the first dataset this config runs on
    for (const auto& d : sweep.datasets)
      if (sweep.runs(c, d)) {
        if (!runs) runs = &d;
        build(c, d, first, "config " + name(c) + ", dataset " + d.name);
      }
    if (!runs) continue;
    // Other swept values on the first dataset, so a value that does not fit its parameter fails
    // now, not in the middle of the sweep. A parameter's range is an interval, so a number key's
    // smallest and largest values stand for all of them; every other kind of value is built once.
    for (size_t a = 0; a < sweep.axes.size(); ++a)
      for (size_t i : pointsToCheck(sweep.axes[a])) {
        std::vector<size_t> point = first;
        point[a] = i;
        build(c, *runs, point, "config " + name(c));
      }
  }
  if (errors.size() == 1) throw errors[0];
  if (!errors.empty()) throw ConfigErrorList(errors);
}

std::string caseDir(const std::string& dir, const std::string& id) {
  return (fs::path(dir) / "cases" / id).string();
}

bool hasResult(const std::string& dir, const std::string& id) {
  return ::access((caseDir(dir, id) + "/result.json").c_str(), F_OK) == 0;
}

CaseCommand caseCommand(const Case& c, const std::string& self, const std::string& case_dir,
                        const std::string& cwd) {
  CaseCommand cmd;
  cmd.cwd = cwd;
  cmd.argv = {self, "run", c.config, "-o", (fs::path(case_dir) / "out").string()};
  for (const auto& o : c.overrides) {
    cmd.argv.push_back("--set");
    cmd.argv.push_back(o);
  }
  return cmd;
}

namespace {
json targetsJson(const std::vector<Target>& targets) {
  json out = json::array();
  for (const auto& t : targets)
    out.push_back({{"metric", t.metric}, {"at_most", t.at_most}, {"value", t.value}, {"of", t.of}});
  return out;
}
}  // namespace

void writePlan(const Plan& plan, const std::string& dir, const std::string& self) {
  const fs::path root = fs::absolute(dir);
  fs::create_directories(root / "cases");
  const std::string cwd = fs::current_path().string();
  const json evaluation = evaluationJson(plan.evaluators, plan.custom_metrics);
  json cases = json::array();
  std::string tsv = "index\tid\tconfig\tdataset\trepeat\tparameters\n";
  std::string script =
      "# Every case of the sweep, one command a line, in plan order (each is also the 'command'\n"
      "# of its cases/ID/case.json).\n";
  for (size_t i = 0; i < plan.cases.size(); ++i) {
    const Case& c = plan.cases[i];
    const std::string cdir = caseDir(root.string(), c.id);
    const CaseCommand cmd = caseCommand(c, self, cdir, cwd);
    std::string line = "cd " + shellQuote(cmd.cwd) + " &&";
    for (const auto& a : cmd.argv) line += " " + shellQuote(a);
    json params = json::array();
    std::string params_text;
    for (const auto& [k, v] : c.params) {
      params.push_back({k, v});
      params_text += (params_text.empty() ? "" : " ") + k + "=" + v;
    }
    json one{{"id", c.id},
             {"config", c.config},
             {"config_label", c.config_label},
             {"dataset", c.dataset},
             {"params", params},
             {"repeat", c.repeat},
             {"overrides", c.overrides},
             {"source_path", c.source_path},
             {"scoring", scoringJson(c.scoring)}};
    json case_json = one;
    case_json["command"] = line;
    case_json["argv"] = cmd.argv;
    case_json["cwd"] = cmd.cwd;
    case_json["metrics"] = plan.metrics;
    if (!plan.evaluators.empty()) case_json["evaluation"] = evaluation;
    case_json["timeout_s"] = plan.timeout_s;
    // A finished case keeps the files it ran from; any other is written afresh (the binary or
    // the folders may have moved since).
    if (::mkdir(cdir.c_str(), 0755) == 0) {
      writeSmallFile(cdir + "/case.json", case_json.dump(2) + "\n");
    } else if (!hasResult(root.string(), c.id)) {
      // Reading is cheaper than truncating and writing again, and a plan run again is the usual
      // case: a resumed sweep.
      const std::string text = case_json.dump(2) + "\n";
      if (readSmallFile(cdir + "/case.json") != text) writeSmallFile(cdir + "/case.json", text);
    }
    script += line + "\n";
    cases.push_back(std::move(one));
    tsv += fmt::format("{}\t{}\t{}\t{}\t{}\t{}\n", i + 1, c.id, c.config_label, c.dataset,
                       c.repeat, params_text);
  }
  json doc{{"sweep_file", plan.sweep_file},   {"metrics", plan.metrics},
           {"swept_keys", plan.swept_keys},   {"configs", plan.config_labels},
           {"datasets", plan.datasets},       {"timeout_s", plan.timeout_s},
           {"title", plan.title},             {"notes", plan.notes},
           {"targets", targetsJson(plan.targets)}, {"evaluation", evaluation},
           {"self", self},                    {"cases", std::move(cases)}};
  writeSmallFile((root / "cases.tsv").string(), tsv);
  writeSmallFile((root / "commands.sh").string(), script);
  writeSmallFile((root / "plan.json").string(), doc.dump() + "\n");
}

Plan readPlan(const std::string& dir) {
  const std::string path = (fs::path(dir) / "plan.json").string();
  std::ifstream in(path);
  if (!in) throw InputError("'" + dir + "' is no sweep folder: no plan.json (`plugslam sweep plan FILE -o " + dir + "` writes one)");
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(path + ": " + e.what());
  }
  Plan plan;
  plan.sweep_file = doc.value("sweep_file", "");
  plan.metrics = doc.value("metrics", std::vector<std::string>{});
  plan.swept_keys = doc.value("swept_keys", std::vector<std::string>{});
  plan.config_labels = doc.value("configs", std::vector<std::string>{});
  plan.datasets = doc.value("datasets", std::vector<std::string>{});
  plan.timeout_s = doc.value("timeout_s", 0.0);
  plan.title = doc.value("title", "");
  plan.notes = doc.value("notes", "");
  evaluationFrom(doc.value("evaluation", json::object()), plan.evaluators, plan.custom_metrics);
  for (const auto& t : doc.value("targets", json::array()))
    plan.targets.push_back(
        Target{t.at("metric"), t.at("at_most"), t.at("value"), t.value("of", std::string())});
  for (const auto& j : doc.at("cases")) {
    Case c;
    c.id = j.at("id");
    c.config = j.value("config", "");
    c.config_label = j.value("config_label", "");
    c.dataset = j.value("dataset", "");
    for (const auto& p : j.at("params")) c.params.emplace_back(p.at(0), p.at(1));
    c.repeat = j.value("repeat", 1);
    c.overrides = j.value("overrides", std::vector<std::string>{});
    c.source_path = j.value("source_path", "");
    c.scoring = scoringFrom(j.value("scoring", json::object()));
    plan.cases.push_back(std::move(c));
  }
  return plan;
}

}  // namespace plugslam::runtime::sweep
