#include "sweep/report.h"

#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/filesystem.hpp>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <unordered_map>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "sweep/engines.h"
#include "sweep/metrics.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;
using nlohmann::json;

namespace {

Stats statsOf(std::vector<double> v) {
  Stats s;
  s.count = static_cast<int>(v.size());
  std::sort(v.begin(), v.end());
  s.min = v.front();
  s.max = v.back();
  const size_t n = v.size();
  s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  return s;
}

std::string num(double v) {
  if (v != 0 && (std::fabs(v) >= 1e6 || std::fabs(v) < 1e-4)) return fmt::format("{:.3e}", v);
  std::string s = fmt::format("{:.4g}", v);
  return s;
}

std::string md(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string header(const Plan& p, const std::string& metric) {
  const MetricInfo* m = findMetric(metric, p.custom_metrics);
  return m && !m->unit.empty() ? metric + " [" + m->unit + "]" : metric;
}

bool isBetter(const Plan& p, const std::string& metric, double a, double b) {
  const MetricInfo* m = findMetric(metric, p.custom_metrics);
  if (m && m->better == Better::None) return false;
  return m && m->better == Better::Higher ? a > b : a < b;
}

std::string paramsText(const Case& c) {
  std::string s;
  for (const auto& [k, v] : c.params) s += (s.empty() ? "" : " ") + k + "=" + v;
  return s;
}

// The best median of each metric over the rows; a metric with one row has no best to mark.
std::map<std::string, double> bestOf(const Plan& p, const std::vector<Row>& rows,
                                     const std::vector<std::string>& metrics) {
  std::map<std::string, double> best;
  for (const auto& m : metrics) {
    const MetricInfo* info = findMetric(m, p.custom_metrics);
    if (info && info->better == Better::None) continue;  // a signed figure has no best
    int with = 0;
    for (const auto& r : rows) {
      auto it = r.metrics.find(m);
      if (it == r.metrics.end()) continue;
      ++with;
      if (!best.count(m) || isBetter(p, m, it->second.median, best[m])) best[m] = it->second.median;
    }
    if (with < 2) best.erase(m);
  }
  return best;
}

}  // namespace

SweepTable gatherResults(const std::string& dir) {
  SweepTable t;
  t.plan = readPlan(dir);
  t.results.reserve(t.plan.cases.size());
  std::unordered_map<std::string, size_t> row_of;
  for (const auto& c : t.plan.cases) {
    CaseResult r;
    r.c = &c;
    std::ifstream in(caseDir(dir, c.id) + "/result.json");
    if (in) {
      try {
        const json j = json::parse(in);
        r.present = true;
        r.status = j.value("status", "");
        r.error = j.value("error", "");
        if (j.contains("exit_code") && j["exit_code"].is_number()) r.exit_code = j["exit_code"].get<int>();
        if (j.contains("metrics"))
          for (const auto& [k, v] : j["metrics"].items())
            if (v.is_number()) r.metrics[k] = v.get<double>();
        if (j.contains("log_tail")) r.log_tail = j["log_tail"].get<std::vector<std::string>>();
      } catch (const json::exception& e) {
        // A result is written atomically, so a broken one was damaged later: the case reruns.
        r.present = false;
      }
    }
    t.results.push_back(std::move(r));
  }
  std::vector<std::map<std::string, std::vector<double>>> values;
  for (const auto& r : t.results) {
    const std::string key = r.c->groupKey();
    auto [it, inserted] = row_of.emplace(key, t.rows.size());
    if (inserted) {
      Row row;
      row.first = r.c;
      t.rows.push_back(std::move(row));
      values.emplace_back();
    }
    Row& at = t.rows[it->second];
    ++at.runs;
    if (!r.present) ++at.missing;
    else if (r.status == "ok") ++at.ok;
    else ++at.failed;
    for (const auto& [m, v] : r.metrics) values[it->second][m].push_back(v);
  }
  for (size_t i = 0; i < t.rows.size(); ++i)
    for (auto& [m, v] : values[i]) t.rows[i].metrics[m] = statsOf(std::move(v));
  return t;
}

std::string targetVerdict(const Plan& p, const Row& r) {
  if (r.failed > 0 || r.missing > 0 || r.ok == 0)
    return r.ok == 0 ? "no (no result)" : "no (not every run has a result)";
  std::string missed, unjudged;
  const auto add = [](std::string& list, const std::string& what) {
    list += (list.empty() ? "" : "; ") + what;
  };
  for (const auto& target : p.targets) {
    const auto it = r.metrics.find(target.metric);
    double bound = target.value;
    if (!target.of.empty()) {
      // A multiple of another metric (the reference's own score): without it in every run
      // there is nothing to compare with, which is said, not counted as a miss.
      const auto of = r.metrics.find(target.of);
      if (of == r.metrics.end() || of->second.count < r.ok) {
        add(unjudged, target.metric + " not judged: " + target.of + " has no value");
        continue;
      }
      // Against the other metric's least favourable value over the runs.
      bound = target.value * (target.at_most ? of->second.min : of->second.max);
    }
    if (it == r.metrics.end() || it->second.count < r.ok) {
      add(missed, target.metric + " not measured in every run");
      continue;
    }
    // Every run: the worst of them against the bound.
    const double worst = target.at_most ? it->second.max : it->second.min;
    if (target.at_most ? worst <= bound : worst >= bound) continue;
    add(missed, fmt::format("{} {} {} {}", target.metric, num(worst), target.at_most ? ">" : "<",
                            num(bound)));
  }
  if (!missed.empty()) return "no (" + missed + (unjudged.empty() ? "" : "; " + unjudged) + ")";
  return unjudged.empty() ? "yes" : "yes (" + unjudged + ")";
}

std::string reportMarkdown(const SweepTable& t, const std::vector<std::string>& plots) {
  const Plan& p = t.plan;
  size_t present = 0, failed = 0;
  for (const auto& r : t.results) {
    present += r.present;
    failed += r.present && r.status != "ok";
  }
  int repeats = 1;
  for (const auto& c : p.cases) repeats = std::max(repeats, c.repeat);
  // Datasets that name their own configs run with those alone: not always the full product.
  std::set<std::pair<std::string, std::string>> pairs;
  for (const auto& c : p.cases) pairs.emplace(c.config_label, c.dataset);
  std::string out = fmt::format("Sweep `{}`: {} cases ({} x {} grid points{}), {} with a result, {} failed or timed out.\n",
                                p.sweep_file, p.cases.size(), runsOn(p),
                                t.rows.size() / std::max<size_t>(1, pairs.size()),
                                repeats > 1 ? fmt::format(" x {} repeats", repeats) : "", present, failed);
  out += repeats > 1 ? "Cells: the median of the repeats, (min–max) when they differ; " : "Cells: ";
  out += "**bold**: the best value of the column.\n";
  std::vector<std::string> verdicts;  // per row, when the sweep has targets
  if (!p.targets.empty()) {
    size_t met = 0;
    for (const auto& r : t.rows) {
      verdicts.push_back(targetVerdict(p, r));
      met += verdicts.back().rfind("yes", 0) == 0;
    }
    std::string list;
    for (const auto& target : p.targets) list += (list.empty() ? "" : ", ") + target.text();
    out += fmt::format("Targets, met by every run of a grid point: {}; {} of {} grid points meet "
                       "them all.\n",
                       list, met, t.rows.size());
  }
  out += "\n";
  // The table.
  const auto best = bestOf(p, t.rows, p.metrics);
  out += "| config | dataset |";
  std::string rule = "|---|---|";
  for (const auto& k : p.swept_keys) {
    out += " " + md(k) + " |";
    rule += "---|";
  }
  out += " runs |";
  rule += "---|";
  for (const auto& m : p.metrics) {
    out += " " + header(p, m) + " |";
    rule += "---|";
  }
  if (!p.targets.empty()) {
    out += " targets |";
    rule += "---|";
  }
  out += "\n" + rule + "\n";
  for (size_t row = 0; row < t.rows.size(); ++row) {
    const Row& r = t.rows[row];
    out += "| " + md(r.first->config_label) + " | " + md(r.first->dataset) + " |";
    for (const auto& [k, v] : r.first->params) out += " " + md(v) + " |";
    std::string runs = fmt::format("{}", r.ok);
    if (r.runs > 1 || r.failed || r.missing) runs = fmt::format("{}/{}", r.ok, r.runs);
    if (r.failed) runs += fmt::format(", {} failed", r.failed);
    if (r.missing) runs += fmt::format(", {} missing", r.missing);
    out += " " + runs + " |";
    for (const auto& m : p.metrics) {
      auto it = r.metrics.find(m);
      if (it == r.metrics.end()) {
        out += " – |";
        continue;
      }
      const Stats& s = it->second;
      std::string cell = num(s.median);
      auto b = best.find(m);
      if (b != best.end() && s.median == b->second) cell = "**" + cell + "**";
      if (s.count > 1 && s.min != s.max) cell += " (" + num(s.min) + "–" + num(s.max) + ")";
      out += " " + cell + " |";
    }
    if (!verdicts.empty()) out += " " + verdicts[row] + " |";
    out += "\n";
  }
  // Heat tables: dataset x config, the best grid point's median of each; only where a dataset
  // runs with more than one config (else there is nothing to compare).
  std::map<std::string, std::set<std::string>> configs_of;
  for (const auto& c : p.cases) configs_of[c.dataset].insert(c.config_label);
  if (std::any_of(configs_of.begin(), configs_of.end(),
                  [](const auto& d) { return d.second.size() > 1; })) {
    for (const auto& m : p.metrics) {
      std::map<std::pair<std::string, std::string>, double> cell;
      for (const auto& r : t.rows) {
        auto it = r.metrics.find(m);
        if (it == r.metrics.end()) continue;
        const auto key = std::make_pair(r.first->dataset, r.first->config_label);
        auto c = cell.find(key);
        if (c == cell.end() || isBetter(p, m, it->second.median, c->second)) cell[key] = it->second.median;
      }
      // A metric only some configs give (loops, of the SLAM configs) has nothing to compare.
      std::map<std::string, int> given;
      for (const auto& [key, v] : cell) ++given[key.first];
      if (std::none_of(given.begin(), given.end(), [](const auto& g) { return g.second > 1; }))
        continue;
      out += fmt::format("\n{} by dataset and config{} (**bold**: the best config of the dataset):\n\n",
                         header(p, m), p.swept_keys.empty() ? "" : ", the best grid point of each");
      out += "| dataset |";
      rule = "|---|";
      for (const auto& c : p.config_labels) {
        out += " " + md(c) + " |";
        rule += "---|";
      }
      out += "\n" + rule + "\n";
      for (const auto& d : p.datasets) {
        std::optional<double> row_best;
        for (const auto& c : p.config_labels)
          if (auto it = cell.find({d, c}); it != cell.end() && (!row_best || isBetter(p, m, it->second, *row_best)))
            row_best = it->second;
        out += "| " + md(d) + " |";
        for (const auto& c : p.config_labels) {
          auto it = cell.find({d, c});
          if (it == cell.end()) out += " – |";
          else if (p.config_labels.size() > 1 && row_best && it->second == *row_best) out += " **" + num(it->second) + "** |";
          else out += " " + num(it->second) + " |";
        }
        out += "\n";
      }
    }
  }
  // Failures, with what the run said last.
  std::string failures;
  for (const auto& r : t.results) {
    if (!r.present || r.status == "ok") continue;
    failures += fmt::format("- `{}` {}: {}{}{}\n", r.c->id, md(caseLabel(*r.c)), r.status,
                            r.exit_code ? fmt::format(", exit {}", *r.exit_code) : "",
                            r.error.empty() ? "" : ", " + r.error);
    if (!r.log_tail.empty()) {
      failures += "  ```\n";
      for (const auto& line : r.log_tail) failures += "  " + line + "\n";
      failures += "  ```\n";
    }
  }
  if (!failures.empty()) out += "\nFailed or timed out (the log's last lines):\n\n" + failures;
  std::string missing;
  size_t n_missing = 0;
  for (const auto& r : t.results)
    if (!r.present && n_missing++ < 20) missing += fmt::format("- `{}` {}\n", r.c->id, md(caseLabel(*r.c)));
  if (n_missing)
    out += fmt::format("\n{} cases have no result yet (the same `sweep run` runs only those){}:\n\n{}",
                       n_missing, n_missing > 20 ? ", the first 20" : "", missing);
  if (!plots.empty()) {
    out += "\nPlots (each metric against each swept parameter, one line per dataset; the median over the other parameters):\n\n";
    for (const auto& f : plots) out += "- " + f + "\n";
  }
  return out;
}

std::string tableCsv(const SweepTable& t) {
  std::string out = "config,dataset";
  for (const auto& k : t.plan.swept_keys) out += "," + csvField(k);
  out += ",runs,ok,failed,missing";
  for (const auto& m : t.plan.metrics) out += fmt::format(",{0}_median,{0}_min,{0}_max", m);
  out += "\n";
  for (const auto& r : t.rows) {
    out += csvField(r.first->config_label) + "," + csvField(r.first->dataset);
    for (const auto& [k, v] : r.first->params) out += "," + csvField(v);
    out += fmt::format(",{},{},{},{}", r.runs, r.ok, r.failed, r.missing);
    for (const auto& m : t.plan.metrics) {
      auto it = r.metrics.find(m);
      if (it == r.metrics.end()) out += ",,,";
      else out += fmt::format(",{},{},{}", it->second.median, it->second.min, it->second.max);
    }
    out += "\n";
  }
  return out;
}

std::string casesCsv(const SweepTable& t) {
  std::string out = "index,id,config,dataset";
  for (const auto& k : t.plan.swept_keys) out += "," + csvField(k);
  out += ",repeat,status,exit_code";
  for (const auto& m : t.plan.metrics) out += "," + m;
  out += "\n";
  for (size_t i = 0; i < t.results.size(); ++i) {
    const CaseResult& r = t.results[i];
    out += fmt::format("{},{},{},{}", i + 1, r.c->id, csvField(r.c->config_label), csvField(r.c->dataset));
    for (const auto& [k, v] : r.c->params) out += "," + csvField(v);
    out += fmt::format(",{},{},{}", r.c->repeat, r.present ? r.status : "missing",
                       r.exit_code ? std::to_string(*r.exit_code) : "");
    for (const auto& m : t.plan.metrics) {
      auto it = r.metrics.find(m);
      out += it == r.metrics.end() ? "," : fmt::format(",{}", it->second);
    }
    out += "\n";
  }
  return out;
}

std::string compareMarkdown(const SweepTable& after, const SweepTable& before,
                            const std::string& after_name, const std::string& before_name) {
  std::unordered_map<std::string, const Row*> old_rows;
  for (const auto& r : before.rows) old_rows[r.first->groupKey()] = &r;
  std::vector<std::string> metrics;
  for (const auto& m : after.plan.metrics)
    if (std::find(before.plan.metrics.begin(), before.plan.metrics.end(), m) != before.plan.metrics.end())
      metrics.push_back(m);
  std::string out = fmt::format(
      "`{}` (after) against `{}` (before), grid point by grid point; cells: before → after "
      "(change), **bold** where after is better.\n\n| config | dataset | parameters |",
      after_name, before_name);
  std::string rule = "|---|---|---|";
  for (const auto& m : metrics) {
    out += " " + header(after.plan, m) + " |";
    rule += "---|";
  }
  out += "\n" + rule + "\n";
  size_t matched = 0;
  for (const auto& r : after.rows) {
    auto it = old_rows.find(r.first->groupKey());
    if (it == old_rows.end()) continue;
    ++matched;
    out += "| " + md(r.first->config_label) + " | " + md(r.first->dataset) + " | " +
           md(paramsText(*r.first)) + " |";
    for (const auto& m : metrics) {
      auto a = r.metrics.find(m), b = it->second->metrics.find(m);
      if (a == r.metrics.end() || b == it->second->metrics.end()) {
        out += fmt::format(" {} → {} |", b == it->second->metrics.end() ? "–" : num(b->second.median),
                           a == r.metrics.end() ? "–" : num(a->second.median));
        continue;
      }
      const double x = b->second.median, y = a->second.median;
      std::string change = x != 0 ? fmt::format("{:+.1f} %", 100.0 * (y - x) / std::fabs(x))
                                  : fmt::format("{:+.4g}", y - x);
      std::string cell = num(x) + " → " + num(y) + " (" + change + ")";
      if (isBetter(after.plan, m, y, x)) cell = "**" + cell + "**";
      out += " " + cell + " |";
    }
    out += "\n";
  }
  out += fmt::format("\n{} grid points in both; {} only in after, {} only in before.\n", matched,
                     after.rows.size() - matched, before.rows.size() - matched);
  return out;
}

std::string writeReport(const SweepTable& t, const std::string& sweep_dir,
                        const std::string& out_dir, const std::string& compare_dir, bool plots) {
  fs::create_directories(out_dir);
  std::vector<std::string> plot_files;
  if (plots) {
    const fs::path pdir = fs::path(out_dir) / "plots";
    for (const auto& f : drawPlots(t, pdir.string()))
      plot_files.push_back(fs::relative(f, out_dir).string());
  }
  std::string text = reportMarkdown(t, plot_files);
  writeFileAtomically((fs::path(out_dir) / "table.csv").string(), tableCsv(t));
  writeFileAtomically((fs::path(out_dir) / "cases.csv").string(), casesCsv(t));
  if (!compare_dir.empty()) {
    const SweepTable before = gatherResults(compare_dir);
    const std::string cmp = compareMarkdown(t, before, sweep_dir, compare_dir);
    writeFileAtomically((fs::path(out_dir) / "compare.md").string(), cmp);
    text += "\n" + cmp;
  }
  writeFileAtomically((fs::path(out_dir) / "report.md").string(), text);
  return text;
}

namespace {

// The first line a shell command prints (empty when it fails).
std::string firstLineOf(const std::string& command) {
  std::string out;
  if (FILE* p = popen(command.c_str(), "r")) {
    std::array<char, 256> buf{};
    if (fgets(buf.data(), static_cast<int>(buf.size()), p)) out = buf.data();
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

std::string quoted(const std::string& path) {
  std::string q = "'";
  for (char c : path) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

}  // namespace

std::string machineLine(const std::string& repository) {
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      cpu = line.substr(line.find(':') + 1);
      cpu.erase(0, cpu.find_first_not_of(' '));
      break;
    }
  const double gib = static_cast<double>(sysconf(_SC_PHYS_PAGES)) *
                     static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0 * 1024.0);
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::array<char, 16> date{};
  std::strftime(date.data(), date.size(), "%Y-%m-%d", &utc);
  // The code that ran: the repository's commit, "+changes" when its files (not the documents
  // the report writes) differ from it.
  const std::string top =
      firstLineOf("git -C " + quoted(repository) + " rev-parse --show-toplevel 2>/dev/null");
  const std::string git = "git -C " + quoted(top.empty() ? repository : top);
  std::string commit = top.empty() ? "" : firstLineOf(git + " rev-parse --short HEAD 2>/dev/null");
  if (commit.empty()) commit = "unknown";
  else if (!firstLineOf(git + " status --porcelain -uno -- . ':!docs' 2>/dev/null").empty())
    commit += "+changes";
  return fmt::format("Machine: {}, {} cores, {:.0f} GiB; date {}; commit {}.", cpu,
                     std::thread::hardware_concurrency(), std::floor(gib), date.data(), commit);
}

std::string sectionMarkdown(const SweepTable& t, const std::string& sweep_dir,
                            const std::string& section, const std::string& machine) {
  const Plan& p = t.plan;
  std::string out = "## " + (p.title.empty() ? "Sweep " + p.sweep_file : p.title) + "\n\n";
  out += machine + "\n";
  out += fmt::format("Commands: `plugslam sweep run {0} -o {1}`, then `plugslam sweep report {1} "
                     "--section {2}` (any engine: docs/sweeps.md).\n",
                     p.sweep_file, sweep_dir, section);
  if (!p.notes.empty()) out += p.notes + (p.notes.back() == '\n' ? "" : "\n");
  return out + "\n" + reportMarkdown(t, {});
}

void writeSection(const std::string& document, const std::string& section,
                  const std::string& body) {
  const std::string begin = "<!-- " + section + ":begin -->", end = "<!-- " + section + ":end -->";
  std::string text;
  if (std::ifstream in{document}) {
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  } else if (fs::exists(document)) {
    throw InputError("cannot read '" + document + "'");
  }
  std::string block = begin + "\n" + body;
  if (!block.empty() && block.back() != '\n') block += "\n";
  block += end;
  const size_t b = text.find(begin);
  const size_t e = b == std::string::npos ? std::string::npos : text.find(end, b);
  if (b != std::string::npos && e != std::string::npos) {
    text = text.substr(0, b) + block + text.substr(e + end.size());
  } else {
    while (!text.empty() && text.back() == '\n') text.pop_back();
    text += (text.empty() ? "" : "\n\n") + block + "\n";
  }
  writeFileAtomically(document, text);
}

}  // namespace plugslam::runtime::sweep
