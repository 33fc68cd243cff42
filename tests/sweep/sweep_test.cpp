// The sweep file (issue 44): errors located by file:line:col and key, expansion into cases,
// content ids, checks against the configs before anything runs, the report's aggregation.
#include <gtest/gtest.h>

#include <boost/filesystem.hpp>
#include <chrono>
#include <fstream>
#include <set>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "sweep/case_id.h"
#include "sweep/metrics.h"
#include "sweep/plan.h"
#include "sweep/report.h"
#include "sweep/sweep_file.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace fs = boost::filesystem;
using namespace plugslam;
using namespace plugslam::runtime::sweep;

namespace {

// The message of the error parsing `text` throws, or "" when it parses.
std::string errorOf(const std::string& text) {
  try {
    parseSweep(text, "s.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string kMinimal = R"(config: [)" + std::string("configs/sim2d_single_laser.yaml") + R"(]
datasets:
  office-a: {source.seed: 11, source.session: stage-0}
  office-b: {source.seed: 12, source.session: stage-0}
grid:
  pipeline.tracker.splitter.distance: [0.5, 1.0]
metrics: [ate, hz]
)";

}  // namespace

TEST(SweepFile, TheIssuesMinimalFileParses) {
  const SweepFile s = parseSweep(kMinimal, "s.yaml");
  ASSERT_EQ(s.configs.size(), 1u);
  EXPECT_TRUE(fs::exists(s.configs[0]));
  ASSERT_EQ(s.datasets.size(), 2u);
  EXPECT_EQ(s.datasets[0].name, "office-a");
  ASSERT_EQ(s.datasets[0].set.size(), 2u);
  EXPECT_EQ(s.datasets[0].set[0].text(), "source.seed=11");
  ASSERT_EQ(s.axes.size(), 1u);
  EXPECT_EQ(s.axes[0].values[0][0], "0.5");
  EXPECT_EQ(s.axes[0].values[1][0], "1.0");  // as written: the id hashes the text
  EXPECT_EQ(s.metrics, (std::vector<std::string>{"ate", "hz"}));
}

TEST(SweepFile, ErrorsNameFileLineColumnAndKey) {
  EXPECT_EQ(errorOf(kMinimal + "repeats: 3\n"),
            "s.yaml:8:1: repeats: unknown key 'repeats'; did you mean 'repeat'?");
  EXPECT_NE(errorOf("config: configs/sim2d_single_laser.yaml\nmetrics: [ate, rpee]\n").find("s.yaml:2:16: metrics: unknown metric 'rpee'; did you mean 'rpe'?"),
            std::string::npos);
  EXPECT_NE(errorOf("config: [nowhere.yaml]\n").find("s.yaml:1:10: config: no config file 'nowhere.yaml'"),
            std::string::npos);
  const std::string zip = errorOf(kMinimal + "zip: {source.range_noise: [0.01, 0.02], source.dropout: [0.1]}\n");
  EXPECT_NE(zip.find("s.yaml:8:"), std::string::npos) << zip;
  EXPECT_NE(zip.find("source.dropout: has 1 values, the zip's first key 2"), std::string::npos) << zip;
  const std::string twice = errorOf(kMinimal + "set: {pipeline.tracker.splitter.distance: 2}\n");
  EXPECT_NE(twice.find("s.yaml:8:7: pipeline.tracker.splitter.distance: 'pipeline.tracker.splitter.distance' is also swept (line 6)"),
            std::string::npos) << twice;
  EXPECT_NE(errorOf("config: configs/sim2d_single_laser.yaml\ngrid: {a..b: [1]}\n").find("s.yaml:2:8: a..b:"),
            std::string::npos);
  EXPECT_NE(errorOf("config: configs/sim2d_single_laser.yaml\nrepeat: 0\n").find("s.yaml:2:9: repeat: must be at least 1"),
            std::string::npos);
  EXPECT_NE(errorOf("config: [a\n").find("s.yaml:"), std::string::npos);
}

TEST(SweepFile, EveryErrorOfAFileIsReportedAtOnce) {
  const std::string e = errorOf("config: configs/sim2d_single_laser.yaml\nmetric: [ate]\nslurm: {partiton: x}\n");
  EXPECT_NE(e.find("s.yaml:2:1: metric: unknown key 'metric'; did you mean 'metrics'?"), std::string::npos) << e;
  EXPECT_NE(e.find("s.yaml:3:9: partiton: unknown key 'partiton' in slurm; did you mean 'partition'?"), std::string::npos) << e;
  EXPECT_NE(e.find("2 errors"), std::string::npos) << e;
}

TEST(SweepFile, DatasetsLongFormNameWhatTheyAreScoredAgainst) {
  const SweepFile s = parseSweep(
      "config: configs/sim2d_single_laser.yaml\n"
      "datasets:\n"
      "  a: {set: {source.seed: 1}, reference: ref.tum, relations: r.relations, log: x.gz, laser: front}\n"
      "  b: {source.seed: 2}\n",
      "s.yaml");
  EXPECT_EQ(s.datasets[0].scoring.reference, "ref.tum");
  EXPECT_EQ(s.datasets[0].scoring.relations, "r.relations");
  EXPECT_EQ(s.datasets[0].scoring.laser, "front");
  EXPECT_EQ(s.datasets[1].set[0].text(), "source.seed=2");
  EXPECT_NE(errorOf("config: configs/sim2d_single_laser.yaml\ndatasets:\n  a: {source.seed: 1, reference: r.tum}\n")
                .find("s.yaml:3:34: datasets.a.reference: 'reference' belongs with the long form"),
            std::string::npos);
}

TEST(CaseIds, StableAndDifferentWhenAnythingDiffers) {
  const std::string id = caseId("text", {"a=1", "b=2"}, 1);
  EXPECT_EQ(id.size(), 16u);
  EXPECT_EQ(id, caseId("text", {"a=1", "b=2"}, 1));
  // Fixed by the hash's definition, not by this build: the same in every run, on every machine.
  EXPECT_EQ(caseId("", {}, 1), caseId("", {}, 1));
  std::set<std::string> ids{id,
                            caseId("text", {"a=1", "b=3"}, 1),
                            caseId("text", {"a=1", "b=2"}, 2),
                            caseId("text2", {"a=1", "b=2"}, 1),
                            caseId("text", {"a=1b=2"}, 1),
                            caseId("text", {"b=2", "a=1"}, 1),
                            caseId("text", {"a=1.0", "b=2"}, 1)};
  EXPECT_EQ(ids.size(), 7u);
}

TEST(Expansion, ConfigsTimesDatasetsTimesGridTimesRepeats) {
  const std::string text =
      "config: [configs/sim2d_single_laser.yaml, configs/sim2d_double_laser.yaml]\n"
      "datasets: {a: {source.seed: 1}, b: {source.seed: 2}, c: {source.seed: 3}}\n"
      "set: {max_frames: 10}\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, 1.0], pipeline.tracker.splitter.angle: [0.1, 0.2, 0.3]}\n"
      "zip: {source.range_noise: [0.01, 0.02], source.dropout: [0.0, 0.1]}\n"
      "repeat: 2\n";
  const Plan plan = expandSweep(parseSweep(text, "s.yaml"));
  ASSERT_EQ(plan.cases.size(), 2u * 3 * (2 * 3 * 2) * 2);
  const Case& c0 = plan.cases[0];
  EXPECT_EQ(c0.config_label, "sim2d_single_laser");
  EXPECT_EQ(c0.dataset, "a");
  EXPECT_EQ(c0.overrides,
            (std::vector<std::string>{"max_frames=10", "source.seed=1",
                                      "pipeline.tracker.splitter.distance=0.5",
                                      "pipeline.tracker.splitter.angle=0.1",
                                      "source.range_noise=0.01", "source.dropout=0.0"}));
  // Repeats next to each other, the last axis fastest (zipped values together).
  EXPECT_EQ(plan.cases[1].repeat, 2);
  EXPECT_EQ(plan.cases[1].groupKey(), c0.groupKey());
  EXPECT_EQ(plan.cases[2].params.back(), (std::pair<std::string, std::string>{"source.dropout", "0.1"}));
  EXPECT_EQ(plan.cases[2].params[2].second, "0.02");
  std::set<std::string> ids;
  for (const auto& c : plan.cases) ids.insert(c.id);
  EXPECT_EQ(ids.size(), plan.cases.size());
  // Planned again: the same ids in the same order.
  const Plan again = expandSweep(parseSweep(text, "elsewhere/t.yaml"));
  for (size_t i = 0; i < plan.cases.size(); ++i) EXPECT_EQ(again.cases[i].id, plan.cases[i].id);
}

TEST(Validation, AGridKeyThatIsNoParameterFailsBeforeAnythingRuns) {
  runtime::PluginManager plugins;
  const SweepFile bad = parseSweep(
      "config: configs/sim2d_single_laser.yaml\n"
      "datasets: {a: {source.seed: 1}}\n"
      "grid: {pipeline.tracker.splitter.distanc: [0.5, 1.0]}\n",
      "s.yaml");
  try {
    validateSweep(bad, plugins);
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml:3:8: pipeline.tracker.splitter.distanc: unknown key 'distanc'"),
              std::string::npos)
        << e.what();
  }
  const SweepFile bad_value = parseSweep(
      "config: configs/sim2d_single_laser.yaml\n"
      "datasets: {a: {source.session: stage-9}}\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, -3]}\n",
      "s.yaml");
  try {
    validateSweep(bad_value, plugins);
    FAIL() << "no error";
  } catch (const runtime::ConfigErrorList& e) {
    const std::string text = e.what();
    EXPECT_NE(text.find("s.yaml:2:16: source.session:"), std::string::npos) << text;
    EXPECT_NE(text.find("s.yaml:3:8: pipeline.tracker.splitter.distance:"), std::string::npos) << text;
  }
  EXPECT_NO_THROW(validateSweep(parseSweep(kMinimal, "s.yaml"), plugins));
}

TEST(Plan, CasesWriteAndReadBack) {
  // 10,000 cases and their times are the bench's (scripts/bench/sweep_scale.sh): a test keeps
  // the file system's work small.
  std::string grid = "grid:\n  pipeline.tracker.splitter.distance: [";
  for (int i = 0; i < 10; ++i) grid += (i ? ", " : "") + std::to_string(0.1 + 0.01 * i);
  grid += "]\n  pipeline.tracker.splitter.angle: [";
  for (int i = 0; i < 10; ++i) grid += (i ? ", " : "") + std::to_string(0.1 + 0.01 * i);
  grid += "]\n";
  const SweepFile s = parseSweep(
      "config: [configs/sim2d_single_laser.yaml, configs/sim2d_double_laser.yaml]\n" + grid, "s.yaml");
  const Plan plan = expandSweep(s);
  ASSERT_EQ(plan.cases.size(), 200u);
  const plugslam::testing::TempDir temp("sweep-plan");
  const fs::path dir = temp.path().string();
  writePlan(plan, dir.string(), "/bin/true");
  const Plan back = readPlan(dir.string());
  ASSERT_EQ(back.cases.size(), 200u);
  EXPECT_EQ(back.cases[199].id, plan.cases[199].id);
  EXPECT_EQ(back.cases[199].params, plan.cases[199].params);
  EXPECT_TRUE(fs::exists(fs::path(caseDir(dir.string(), plan.cases[42].id)) / "case.json"));
  // The report of a plan without results: every case missing, none lost.
  const SweepTable t = gatherResults(dir.string());
  EXPECT_EQ(t.rows.size(), 200u);
  EXPECT_EQ(t.rows[0].missing, 1);
}

TEST(Report, RepeatsAggregateAndTheBestIsMarked) {
  const plugslam::testing::TempDir temp("sweep-report");
  const fs::path dir = temp.path().string();
  const SweepFile s = parseSweep(
      "config: configs/sim2d_single_laser.yaml\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, 1.0]}\n"
      "repeat: 3\nmetrics: [ate, hz]\n",
      "s.yaml");
  const Plan plan = expandSweep(s);
  writePlan(plan, dir.string(), "/bin/true");
  const double ate[] = {0.3, 0.1, 0.2, 0.05, 0.07, 0.06};
  for (size_t i = 0; i < plan.cases.size(); ++i) {
    std::ofstream(caseDir(dir.string(), plan.cases[i].id) + "/result.json")
        << "{\"status\": \"ok\", \"exit_code\": 0, \"metrics\": {\"ate\": " << ate[i]
        << ", \"hz\": " << 100 + i << "}}\n";
  }
  const SweepTable t = gatherResults(dir.string());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(t.rows[0].metrics.at("ate").median, 0.2);
  EXPECT_DOUBLE_EQ(t.rows[0].metrics.at("ate").min, 0.1);
  EXPECT_DOUBLE_EQ(t.rows[0].metrics.at("ate").max, 0.3);
  EXPECT_DOUBLE_EQ(t.rows[1].metrics.at("hz").median, 104);
  const std::string md = reportMarkdown(t, {});
  EXPECT_NE(md.find("| sim2d_single_laser | default | 0.5 | 3/3 | 0.2 (0.1–0.3) | 101 (100–102) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| sim2d_single_laser | default | 1.0 | 3/3 | **0.06** (0.05–0.07) | **104** (103–105) |"), std::string::npos) << md;
  EXPECT_NE(tableCsv(t).find("default,1.0,3,3,0,0,0.06,0.05,0.07,104,103,105"), std::string::npos) << tableCsv(t);
  // Compared with itself: every grid point matched, no change.
  const std::string cmp = compareMarkdown(t, t, "a", "b");
  EXPECT_NE(cmp.find("2 grid points in both"), std::string::npos) << cmp;
  EXPECT_NE(cmp.find("0.06 → 0.06 (+0.0 %)"), std::string::npos) << cmp;
}

// `sweep report --section`: the tables go between the section's markers of a document, with the
// sweep file's title and notes; the rest of the document is kept, and a second report replaces
// the section rather than adding one.
TEST(Report, ASectionOfADocumentIsWrittenAndReplaced) {
  const plugslam::testing::TempDir temp("sweep-section");
  const fs::path dir = fs::path(temp.path().string()) / "sweep";
  const SweepFile s = parseSweep(
      "title: Splitter distance on the office\n"
      "notes: \"Cells: ATE RMSE [m].\"\n"
      "config: configs/sim2d_single_laser.yaml\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, 1.0]}\nmetrics: [ate]\n",
      "s.yaml");
  EXPECT_EQ(s.title, "Splitter distance on the office");
  const Plan plan = expandSweep(s);
  writePlan(plan, dir.string(), "/bin/true");
  for (size_t i = 0; i < plan.cases.size(); ++i)
    std::ofstream(caseDir(dir.string(), plan.cases[i].id) + "/result.json")
        << "{\"status\": \"ok\", \"exit_code\": 0, \"metrics\": {\"ate\": " << 0.1 + 0.1 * i
        << "}}\n";
  const std::string doc = (fs::path(temp.path().string()) / "benchmarks.md").string();
  std::ofstream(doc) << "# Benchmarks\n\n<!-- other:begin -->\nkept\n<!-- other:end -->\n";
  const SweepTable t = gatherResults(dir.string());
  const std::string machine = "Machine: test.";
  for (int pass = 0; pass < 2; ++pass)
    writeSection(doc, "splitter", sectionMarkdown(t, dir.string(), "splitter", machine));
  std::ifstream in(doc);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<!-- other:begin -->\nkept\n<!-- other:end -->"), std::string::npos) << text;
  EXPECT_NE(text.find("<!-- splitter:begin -->\n## Splitter distance on the office\n\n"
                      "Machine: test.\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("Cells: ATE RMSE [m].\n"), std::string::npos) << text;
  EXPECT_NE(text.find("| sim2d_single_laser | default | 0.5 | 1 | **0.1** |"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("<!-- splitter:begin -->"), text.rfind("<!-- splitter:begin -->")) << text;
  EXPECT_NE(text.find("<!-- splitter:end -->"), std::string::npos);
  // The machine line of a real folder names the CPU and a commit (or says it has none).
  const std::string line = machineLine(temp.path().string());
  EXPECT_EQ(line.rfind("Machine: ", 0), 0u) << line;
  EXPECT_NE(line.find("; commit "), std::string::npos) << line;
}

// `targets`: each grid point's verdict over every run; a target on a metric the sweep does not
// measure, or a condition that is not "<= VALUE" / ">= VALUE", is an error at its line.
TEST(Report, TargetsAreJudgedOverEveryRun) {
  const std::string base =
      "config: configs/sim2d_single_laser.yaml\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, 1.0]}\n"
      "repeat: 2\nmetrics: [ate, hz]\n";
  EXPECT_NE(errorOf(base + "targets: {rpe: \"<= 0.1\"}\n").find("s.yaml:5"), std::string::npos)
      << errorOf(base + "targets: {rpe: \"<= 0.1\"}\n");
  EXPECT_NE(errorOf(base + "targets: {ate: \"< 0.1\"}\n").find("expected \"<= VALUE\""),
            std::string::npos);
  EXPECT_NE(errorOf(base + "targets: {ate: \"<= fast\"}\n").find("targets"), std::string::npos);
  const SweepFile s = parseSweep(base + "targets: {ate: \"<= 0.15\", hz: \">= 100\"}\n", "s.yaml");
  ASSERT_EQ(s.targets.size(), 2u);
  const plugslam::testing::TempDir temp("sweep-targets");
  const fs::path dir = temp.path().string();
  writePlan(expandSweep(s), dir.string(), "/bin/true");
  const Plan plan = readPlan(dir.string());
  ASSERT_EQ(plan.targets.size(), 2u);
  EXPECT_EQ(plan.targets[1].text(), "hz >= 100");
  // Distance 0.5: one of its two runs misses the ATE bound; 1.0: both meet both.
  const double ate[] = {0.1, 0.2, 0.05, 0.06};
  for (size_t i = 0; i < plan.cases.size(); ++i)
    std::ofstream(caseDir(dir.string(), plan.cases[i].id) + "/result.json")
        << "{\"status\": \"ok\", \"exit_code\": 0, \"metrics\": {\"ate\": " << ate[i]
        << ", \"hz\": " << 100 + i << "}}\n";
  const SweepTable t = gatherResults(dir.string());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(targetVerdict(t.plan, t.rows[0]), "no (ate 0.2 > 0.15)");
  EXPECT_EQ(targetVerdict(t.plan, t.rows[1]), "yes");
  const std::string md = reportMarkdown(t, {});
  EXPECT_NE(md.find("1 of 2 grid points meet them all"), std::string::npos) << md;
  EXPECT_NE(md.find("| yes |"), std::string::npos) << md;
}

namespace {

// Writes one result per case of the sweep in `dir`, metrics as JSON text per case.
void writeResults(const std::string& dir, const Plan& plan, const std::vector<std::string>& metrics) {
  for (size_t i = 0; i < plan.cases.size(); ++i)
    std::ofstream(caseDir(dir, plan.cases[i].id) + "/result.json")
        << "{\"status\": \"ok\", \"exit_code\": 0, \"metrics\": {" << metrics[i] << "}}\n";
}

}  // namespace

// A target may be a multiple of another metric of the same run (a map as crisp as the
// reference's, 0.9 of its coverage); where that metric has no value the target is not judged,
// and the verdict says so rather than passing or failing it silently.
TEST(Report, RelativeTargetsCompareWithAnotherMetric) {
  const std::string base =
      "config: configs/sim2d_single_laser.yaml\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, 1.0, 2.0]}\n"
      "metrics: [crispness, coverage, crispness_ref, coverage_ref]\n";
  EXPECT_NE(errorOf(base + "targets: {coverage: \">= 0.9 * hz\"}\n").find("'hz' (in the target"),
            std::string::npos)
      << errorOf(base + "targets: {coverage: \">= 0.9 * hz\"}\n");
  EXPECT_NE(errorOf(base + "targets: {coverage: \">= 0.9 * \"}\n").find("FACTOR"),
            std::string::npos);
  const SweepFile s = parseSweep(
      base + "targets: {crispness: \"<= crispness_ref\", coverage: \">= 0.9 * coverage_ref\"}\n",
      "s.yaml");
  ASSERT_EQ(s.targets.size(), 2u);
  EXPECT_EQ(s.targets[0].text(), "crispness <= crispness_ref");
  EXPECT_EQ(s.targets[1].text(), "coverage >= 0.9 * coverage_ref");
  const plugslam::testing::TempDir temp("sweep-relative");
  const std::string dir = temp.path().string();
  writePlan(expandSweep(s), dir, "/bin/true");
  const Plan plan = readPlan(dir);
  ASSERT_EQ(plan.targets.size(), 2u);
  EXPECT_EQ(plan.targets[1].of, "coverage_ref");
  // 0.5: as crisp as the reference, too little coverage; 1.0: both met; 2.0: the reference's
  // crispness could not be measured (no overlap), so crispness is not judged.
  writeResults(dir, plan,
               {"\"crispness\": 0.02, \"coverage\": 0.8, \"crispness_ref\": 0.03, "
                "\"coverage_ref\": 1.0",
                "\"crispness\": 0.02, \"coverage\": 0.95, \"crispness_ref\": 0.03, "
                "\"coverage_ref\": 1.0",
                "\"coverage\": 0.0, \"coverage_ref\": 0.0"});
  const SweepTable t = gatherResults(dir);
  ASSERT_EQ(t.rows.size(), 3u);
  EXPECT_EQ(targetVerdict(t.plan, t.rows[0]), "no (coverage 0.8 < 0.9)");
  EXPECT_EQ(targetVerdict(t.plan, t.rows[1]), "yes");
  EXPECT_EQ(targetVerdict(t.plan, t.rows[2]),
            "yes (crispness not judged: crispness_ref has no value)");
  EXPECT_NE(reportMarkdown(t, {}).find("2 of 3 grid points meet them all"), std::string::npos);
}

// The front-end's figures a sweep reads from run.json: the graph's pieces, the ambiguous frames
// and the time split of search, refine and merge.
TEST(Metrics, RunJsonGivesComponentsAmbiguityAndTheTimeSplit) {
  const plugslam::testing::TempDir temp("sweep-metrics");
  const std::string dir = temp.path().string();
  std::ofstream(dir + "/run.json")
      << R"({"tracking_ambiguous": 3, "tracking_time_s": {"search": 1.5, "refine": 0.25,
             "merge": 0.125}, "graph": {"components": [{"first_map": 0, "maps": 4},
             {"first_map": 4, "maps": 2}]}})";
  RunFacts run;
  run.out_dir = dir;
  const MetricValues m = measure({"components", "ambiguous", "search_s", "refine_s", "merge_s"},
                                 Scoring{}, run, "/bin/false", dir, "");
  EXPECT_EQ(m.values.at("components"), 2.0);
  EXPECT_EQ(m.values.at("ambiguous"), 3.0);
  EXPECT_EQ(m.values.at("search_s"), 1.5);
  EXPECT_EQ(m.values.at("refine_s"), 0.25);
  EXPECT_EQ(m.values.at("merge_s"), 0.125);
  // Without a graph there is no component count, and the reason is given.
  std::ofstream(dir + "/run.json") << "{}";
  const MetricValues none = measure({"components"}, Scoring{}, run, "/bin/false", dir, "");
  EXPECT_FALSE(none.values.at("components").has_value());
  EXPECT_NE(none.errors.at("components").find("no graph"), std::string::npos);
}

// A sweep's own evaluation: a shell command on each finished run whose JSON output gives
// metrics (dot paths), listed in `metrics` like the others; the placeholders are the run's files.
TEST(Metrics, AnEvaluatorsCommandGivesMetrics) {
  const std::string base = "config: configs/sim2d_single_laser.yaml\n";
  const std::string evaluators =
      "evaluators:\n"
      "  steps:\n"
      "    command: \"test -f {trajectory} && printf '{\\\"worst\\\": {\\\"percent\\\": 4.5}, "
      "\\\"steps\\\": [1.5, 2.5]}'\"\n"
      "    metrics:\n"
      "      worst_step: {key: worst.percent, unit: \"%\", better: lower}\n"
      "      second_step: {key: \"steps[1]\"}\n"
      "      missing: {key: worst.nothing}\n";
  EXPECT_NE(errorOf(base + evaluators + "metrics: [worst_stp]\n").find("did you mean 'worst_step'"),
            std::string::npos);
  EXPECT_NE(errorOf(base + "evaluators: {e: {command: x, metrics: {ate: {key: a}}}}\n")
                .find("'ate' is already a metric"),
            std::string::npos);
  // A key is a path as `--set` writes one, checked when the file is read.
  EXPECT_NE(errorOf(base + "evaluators: {e: {command: x, metrics: {m: {key: \"a..b\"}}}}\n")
                .find("malformed parameter path 'a..b'"),
            std::string::npos);
  EXPECT_NE(errorOf(base + "evaluators: {e: {command: x, metrics: {m: {key: a, better: up}}}}\n")
                .find("expected 'lower', 'higher' or 'none'"),
            std::string::npos);
  const SweepFile s =
      parseSweep(base + evaluators + "metrics: [worst_step, second_step, missing]\n", "s.yaml");
  ASSERT_EQ(s.custom_metrics.size(), 3u);
  // Through plan.json, as the case runner and the report read it.
  const plugslam::testing::TempDir temp("sweep-evaluators");
  const std::string dir = temp.path().string();
  writePlan(expandSweep(s), dir, "/bin/true");
  const Plan plan = readPlan(dir);
  ASSERT_EQ(plan.evaluators.size(), 1u);
  ASSERT_EQ(plan.custom_metrics.size(), 3u);
  EXPECT_EQ(findMetric("worst_step", plan.custom_metrics)->unit, "%");
  std::ofstream(dir + "/trajectory.tum") << "0 0 0 0 0 0 0 1\n";
  std::ofstream(dir + "/run.json") << "{}";
  RunFacts run;
  run.out_dir = dir;
  const MetricValues m = measure({"worst_step", "second_step", "missing"}, Scoring{}, run,
                                 "/bin/false", dir, "", plan.evaluators, plan.custom_metrics);
  EXPECT_EQ(m.values.at("worst_step"), 4.5);
  EXPECT_EQ(m.values.at("second_step"), 2.5);
  EXPECT_FALSE(m.values.at("missing").has_value());
  EXPECT_NE(m.errors.at("missing").find("no number at 'worst.nothing'"), std::string::npos);
  // A dataset whose `evaluate` leaves the evaluator out gets no value, and says why.
  Scoring others;
  others.evaluate = {"other"};
  const MetricValues skipped = measure({"worst_step"}, others, run, "/bin/false", dir, "",
                                       plan.evaluators, plan.custom_metrics);
  EXPECT_NE(skipped.errors.at("worst_step").find("does not run 'steps'"), std::string::npos);
  EXPECT_NE(errorOf(base + evaluators + "datasets: {a: {set: {}, evaluate: [stpes]}}\n")
                .find("no evaluator 'stpes'"),
            std::string::npos);
  // Without the run's trajectory the command fails, and the reason is kept.
  fs::remove(dir + "/trajectory.tum");
  const MetricValues failed = measure({"worst_step"}, Scoring{}, run, "/bin/false", dir, "",
                                      plan.evaluators, plan.custom_metrics);
  EXPECT_FALSE(failed.values.at("worst_step").has_value());
  EXPECT_NE(failed.errors.at("worst_step").find("evaluator 'steps' failed (exit 1)"),
            std::string::npos)
      << failed.errors.at("worst_step");
}

// A dataset only some pipelines can read names its configs: it runs with those alone, and the
// file's `config` may be left out when every dataset names its own.
TEST(Expansion, ADatasetMayNameItsOwnConfigs) {
  const SweepFile s = parseSweep(
      "config: configs/sim2d_single_laser.yaml\n"
      "datasets:\n"
      "  office: {source.session: stage-0}\n"
      "  two-lasers: {config: configs/sim2d_double_laser.yaml, set: {source.session: stage-1}}\n",
      "s.yaml");
  const Plan plan = expandSweep(s);
  ASSERT_EQ(plan.cases.size(), 2u);
  EXPECT_EQ(plan.cases[0].config_label, "sim2d_single_laser");
  EXPECT_EQ(plan.cases[0].dataset, "office");
  EXPECT_EQ(plan.cases[1].config_label, "sim2d_double_laser");
  EXPECT_EQ(plan.cases[1].dataset, "two-lasers");
  EXPECT_NO_THROW(parseSweep(
      "datasets:\n  a: {config: configs/sim2d_single_laser.yaml, set: {source.seed: 1}}\n",
      "s.yaml"));
  EXPECT_NE(errorOf("datasets:\n  a: {source.seed: 1}\n").find("missing key 'config'"),
            std::string::npos);
  EXPECT_NE(errorOf("config: configs/sim2d_single_laser.yaml\n"
                    "datasets:\n  a: {config: configs/sim2d_double_laser.yaml, set: {}}\n")
                .find("runs on no dataset"),
            std::string::npos);
}

// The project's own benches are sweep files (scripts/bench/*.sweep.yaml): each reads without an
// error and plans cases, so a change to the sweep keys or the metrics cannot leave one broken
// until the next bench run. (Their datasets' files are checked when a bench plans them.)
TEST(SweepFile, TheBenchesSweepFilesRead) {
  const fs::path benches = fs::path(plugslam::testing::sourceDir()) / "scripts" / "bench";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(benches)) {
    const std::string name = entry.path().filename().string();
    if (name.size() < 11 || name.substr(name.size() - 11) != ".sweep.yaml") continue;
    ++files;
    try {
      const SweepFile s = readSweepFile(entry.path().string());
      EXPECT_FALSE(expandSweep(s).cases.empty()) << name;
      for (const auto& m : s.metrics) EXPECT_NE(findMetric(m, s.custom_metrics), nullptr) << name;
    } catch (const InputError& e) {
      ADD_FAILURE() << name << ": " << e.what();
    }
  }
  EXPECT_GE(files, 6);
}

// A signed figure (a drift's sign says its direction) is neither better low nor high: the report
// marks no best value of it, where it marks the others'.
TEST(Report, ASignedFigureHasNoBest) {
  const SweepFile s = parseSweep(
      "config: configs/sim2d_single_laser.yaml\n"
      "grid: {pipeline.tracker.splitter.distance: [0.5, 1.0]}\n"
      "evaluators: {e: {command: \"true\", metrics: {drift: {key: d, better: none}}}}\n"
      "metrics: [drift, ate]\n",
      "s.yaml");
  const plugslam::testing::TempDir temp("sweep-signed");
  const std::string dir = temp.path().string();
  writePlan(expandSweep(s), dir, "/bin/true");
  const Plan plan = readPlan(dir);
  ASSERT_EQ(findMetric("drift", plan.custom_metrics)->better, Better::None);
  writeResults(dir, plan, {"\"drift\": -3.5, \"ate\": 0.25", "\"drift\": 1.5, \"ate\": 0.125"});
  const std::string md = reportMarkdown(gatherResults(dir), {});
  EXPECT_NE(md.find("| -3.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 1.5 |"), std::string::npos) << md;
  EXPECT_NE(md.find("**0.125**"), std::string::npos) << md;
}
