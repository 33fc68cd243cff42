// The plugslam CLI as a user runs it: output, exit codes (0 ok, 1 runtime failure, 2 bad input).
#include <gtest/gtest.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "plugslam/version.h"
#include "run_command.h"
#include "temp_dir_test.h"
#include "test_paths.h"

namespace fs = std::filesystem;

namespace {

std::string buildDir() { return plugslam::testing::buildDir(); }

using Result = plugslam::testing::CommandResult;
using plugslam::testing::expectHas;
using plugslam::testing::expectHasAll;

Result run(const std::string& args, const std::string& env = "") {
  return plugslam::testing::runCommand(env + " " + buildDir() + "/bin/plugslam " + args);
}

// Runs plugslam on a pseudo-terminal (stdout and stderr both, 200 columns) from `cwd`: what a
// user sees on a terminal, escape sequences included.
Result runOnTerminal(const std::vector<std::string>& args, const fs::path& cwd) {
  int master = -1;
  winsize ws{};
  ws.ws_col = 200;
  ws.ws_row = 50;
  const pid_t pid = forkpty(&master, nullptr, nullptr, &ws);
  if (pid < 0) return {-1, "forkpty failed"};
  if (pid == 0) {
    if (::chdir(cwd.c_str()) != 0) _exit(126);
    const std::string bin = buildDir() + "/bin/plugslam";
    std::vector<char*> argv{const_cast<char*>(bin.c_str())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(bin.c_str(), argv.data());
    _exit(127);
  }
  std::string out;
  char buf[4096];
  for (ssize_t n; (n = ::read(master, buf, sizeof buf)) > 0;) out.append(buf, n);  // EIO at exit
  ::close(master);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

// Every log line of a terminal's output starts on a line of its own: at the start, after a
// newline, or after the status line was erased (CR, erase to end of line).
void expectLogLinesStartClean(const std::string& out) {
  static const std::regex stamp(R"(\[\d\d:\d\d:\d\d\.\d{3}\])");
  int lines = 0;
  for (auto it = std::sregex_iterator(out.begin(), out.end(), stamp); it != std::sregex_iterator();
       ++it, ++lines) {
    const std::string before = out.substr(0, it->position());
    const bool clean = before.empty() || before.back() == '\n' ||
                       (before.size() >= 4 && before.compare(before.size() - 4, 4, "\r\033[K") == 0);
    EXPECT_TRUE(clean) << "log line at byte " << it->position() << " follows: '"
                       << before.substr(before.size() > 60 ? before.size() - 60 : 0) << "'";
  }
  EXPECT_GT(lines, 0) << out;
}

class Cli : public plugslam::testing::TempDirTest {
 protected:
  Cli() : TempDirTest("plugslam_cli") {}
  // A config file `name` that loads the test fixture plugin, then says `body`.
  std::string fixtureConfig(const std::string& name, const std::string& body) {
    return write(name, "plugins: [" + buildDir() + "/tests/plugins/plugslam_fixture.so]\n" + body);
  }
  std::string config(const std::string& extra = "") {
    return fixtureConfig("run.yaml",
                         "source: {type: fixture.CountingSource, frames: 20}\n"
                         "pipeline:\n  preprocessors:\n    - {type: fixture.Scale, factor: 0.5}\n"
                         "outputs: [fixture.SumWriter]\n" +
                             extra);
  }
};

}  // namespace

TEST_F(Cli, VersionAndHelp) {
  auto r = run("--version");
  expectExit(r, 0,
             {std::string("plugslam ") + PLUGSLAM_VERSION_STRING + " (plugin ABI " +
              std::to_string(PLUGSLAM_ABI_MAJOR) + "." + std::to_string(PLUGSLAM_ABI_MINOR) + ")"});
  r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (auto c : {"plugins", "describe", "config", "validate", "run", "reference"}) expectHas(r.out, c);
  r = run("frobnicate");
  EXPECT_EQ(r.code, 2);
}

TEST_F(Cli, PluginsListsTypesAndRefusals) {
  auto r = run("plugins", "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins/bad:" + buildDir() +
                              "/tests/plugins");
  expectExit(r, 0,
             {"sdk.Pipeline", "fixture.CountingSource", "refused: plugin 'wrongabi'",
              "refused: plugin 'wrongfingerprint'"});
}

TEST_F(Cli, DescribeAndDefaults) {
  auto r = run("describe fixture.Scale", "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins");
  expectExit(r, 0, {"fixture.Scale (PreProcessor, plugin fixture)", "factor", "default 2"});
  r = run("describe sdk.Pipelin");
  expectExit(r, 2, {"did you mean 'sdk.Pipeline'?"});
  r = run("config --defaults fixture.CountingSource",
          "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins");
  expectExit(r, 0, {"type: fixture.CountingSource", "frames: 10"});
}

TEST_F(Cli, ValidateGoodAndBroken) {
  auto good = config();
  auto r = run("validate " + good);
  expectExit(r, 0, {"OK"});
  auto bad = fixtureConfig("bad.yaml", "source: {type: fixture.CountingSource, frams: 3}\n");
  r = run("validate " + bad);
  expectExit(r, 2, {bad + ":2:40: source.frams: unknown key 'frams'", "did you mean 'frames'?"});
  r = run("validate " + good + " --set pipeline.preprocessors[0].factor=abc");
  expectExit(r, 2,
             {"--set pipeline.preprocessors[0].factor=abc: pipeline.preprocessors[0].factor: "
              "expected a number"});
  r = run("validate " + (dir_ / "missing.yaml").string());
  expectExit(r, 2, {"cannot open config file"});
}

// Item 17.31: validate lists every error of the file, each on its own line with file:line:column
// and the key path, then a count; the missing source is one of them, not a later surprise.
TEST_F(Cli, ValidateReportsEveryError) {
  auto bad = fixtureConfig("bad.yaml",
                           "pipeline:\n"
                           "  preprocessors:\n"
                           "    - {type: fixture.Scale, factr: 0.5}\n"
                           "    - {type: fixture.Scale, factor: abc}\n"
                           "outputs: [fixture.SumWritr]\n");
  auto r = run("validate " + bad);
  expectExit(r, 2,
             {"[error] " + bad + ":1:1: source: missing 'source:'",
              "[error] " + bad + ":4:29: pipeline.preprocessors[0].factr: unknown key 'factr'",
              "[error] " + bad + ":5:37: pipeline.preprocessors[1].factor: expected a number",
              "[error] " + bad + ":6:11: outputs[0]: unknown type 'fixture.SumWritr'",
              "[error] 4 errors in " + bad});
}

// Item 17.7: a tracker that has nothing to align with (no aligner slices) is a configuration
// error, not a run whose pose never moves.
TEST_F(Cli, ValidateRejectsATrackerWithoutAlignerSlices) {
  auto no_slices = fixtureConfig("no_slices.yaml",
                                 "source: {type: fixture.CountingSource}\n"
                                 "pipeline:\n"
                                 "  tracker: {type: sdk.MultiTracker3D}\n");
  auto r = run("validate " + no_slices);
  expectExit(r, 2, {"pipeline.tracker.aligner.slices: the aligner has no slices"});
}

// Item 17.6: validate checks the wiring of the entries: a slice's measurement that no
// preprocessor writes, a scene entry no tracker slice writes (also for the back-end's slices,
// whose measurement is a local map's scene), a preprocessor input the source does not provide.
// Each error names where (the file's line and column, or the --set), the key path and a
// did-you-mean.
TEST_F(Cli, ValidateChecksTheEntryWiring) {
  const std::string shipped = plugslam::testing::sourceDir() + "/configs/sim2d_double_laser.yaml";
  auto r = run("validate " + shipped + " --set pipeline.tracker.aligner.slices[0].measurement=frnt");
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out,
            "--set pipeline.tracker.aligner.slices[0].measurement=frnt: "
            "pipeline.tracker.aligner.slices[0].measurement: no preprocessor writes measurement "
            "entry 'frnt' (laser2d.PointCloud2D); did you mean 'front'?; the preprocessors "
            "write: front, rear");
  auto bad = write("bad.yaml",
                   "plugins: [sim, laser2d, odometry]\n"
                   "source: {type: sim.Simulator2D, session: stage-0}\n"
                   "pipeline:\n"
                   "  preprocessors:\n"
                   "    - {type: laser2d.ScanPreprocessor, input: front_lasr, output: front}\n"
                   "  tracker:\n"
                   "    type: sdk.MultiTracker2D\n"
                   "    motion: {type: odometry.WheelOdometry}\n"
                   "    aligner:\n"
                   "      slices:\n"
                   "        - {type: laser2d.PointToLineSlice, measurement: front, scene: frnt}\n"
                   "    slices:\n"
                   "      - {type: laser2d.PointMapSlice, measurement: front, scene: front}\n"
                   "  graph:\n"
                   "    type: sdk.GraphSlam2D\n"
                   "    loop_detectors: [sdk.ProximityDetector]\n"
                   "    validators:\n"
                   "      - type: sdk.AlignmentValidator2D\n"
                   "        aligner:\n"
                   "          slices: [{type: laser2d.PointToLineSlice, measurement: rear, "
                   "scene: front}]\n");
  r = run("validate " + bad);
  expectExit(r, 2,
             {bad + ":5:47: pipeline.preprocessors[0].input: the source (sim.Simulator2D) "
                    "provides no raw entry 'front_lasr' (plugslam::LaserScan); did you mean "
                    "'front_laser'?; it provides: front_laser, ground_truth, odom, rear_laser",
              bad + ":11:71: pipeline.tracker.aligner.slices[0].scene: no tracker slice "
                    "writes scene entry 'frnt' (laser2d.PointCloud2D); did you mean 'front'?",
              bad + ":20:66: pipeline.graph.validators[0].aligner.slices[0].measurement: no "
                    "tracker slice writes scene entry 'rear' (in the back-end a slice's "
                    "measurement is a local map's scene)",
              "3 errors in " + bad});
  // The shipped configs are wired right (EveryShippedConfigValidates), and so is this one fixed.
  r = run("validate " + shipped);
  EXPECT_EQ(r.code, 0) << r.out;
}

TEST_F(Cli, RunWritesOutputsAndRunJson) {
  auto cfg = config();
  auto out = (dir_ / "out").string();
  auto r = run("run " + cfg + " -o " + out + " --set source.frames=8 -q");
  EXPECT_EQ(r.code, 0) << r.out;
  std::ifstream sum(out + "/sum.txt");
  int frames = 0;
  double total = 0;
  sum >> frames >> total;
  EXPECT_EQ(frames, 8);
  EXPECT_DOUBLE_EQ(total, 0.5 * (0 + 1 + 2 + 3 + 4 + 5 + 6 + 7));
  std::ifstream json(out + "/run.json");
  std::stringstream ss;
  ss << json.rdbuf();
  expectHas(ss.str(), "\"frames\": 8");
  expectHas(ss.str(), "\"pipeline.preprocessors[0]\"");
}

TEST_F(Cli, RuntimeFailureNamesTheModuleAndExitsOne) {
  auto cfg = config();
  auto r = run("run " + cfg + " -o " + (dir_ / "out").string() + " --set source.fail_at=3");
  expectExit(r, 1, {"module 'source' (fixture.CountingSource) failed: fixture failure at frame 3"});
}

namespace {
std::string tum(double t0, double dx, int n) {
  std::string s = "# t x y z qx qy qz qw\n";
  for (int i = 0; i < n; ++i) s += std::to_string(t0 + i) + " " + std::to_string(i * dx) + " 0 0 0 0 0 1\n";
  return s;
}
}  // namespace

TEST_F(Cli, EvalAteRpeRelations) {
  auto ref = write("ref.tum", tum(0, 1.0, 20));
  auto est = write("est.tum", tum(0, 1.1, 20));
  auto r = run("eval ate " + ref + " " + ref);
  expectExit(r, 0, {"rmse"});
  r = run("eval ate " + ref + " " + est + " --align none --format json");
  expectExit(r, 0, {"\"rmse\""});
  r = run("eval rpe " + ref + " " + est + " --unit frames --delta 1 --format json");
  expectExit(r, 0, {"0.1"});  // every step is 0.1 m too long
  r = run("eval relations " + est + " --reference " + ref + " --max-distance 2");
  EXPECT_EQ(r.code, 0) << r.out;
  auto late = write("late.tum", tum(1000, 1.0, 5));
  r = run("eval ate " + ref + " " + late);
  expectExit(r, 2, {"no overlap"});
  auto bad = write("bad.tum", "0 1 2 3\n");
  r = run("eval ate " + ref + " " + bad);
  expectExit(r, 2, {"bad.tum:1"});
}

// The relations file and estimate of tests/eval/relations_test.cpp's HandComputedRelationsFile,
// through the command: 3 of 6 relations used (one misses t1, one t2, one both), translation
// 0.1, 0, 0.05 m (mean 0.05, std 0.05), rotation 0, 2, 3 deg (mean 5/3, std sqrt(7/3)).
TEST_F(Cli, EvalRelationsAgainstAHandComputedFile) {
  auto est = write("est.tum",
                   "1000.000001 0 0 0 0 0 0 1\n"
                   "1000.100002 1 0 0 0 0 0.70710678118654757 0.70710678118654757\n"
                   "1000.200003 1 1 0 0 0 0.70710678118654757 0.70710678118654757\n"
                   "1000.300004 0 1 0 0 0 1 0\n");
  auto rel = write("hand.relations",
                   "1000.000001 1000.100002 1.1 0 0 0 0 1.5707963267948966\n"
                   "1000.100002 1000.200003 1 0 0 0 0 0.034906585039886591\n"
                   "1000.000001 1000.300004 0.03 0.96 0 0 0 3.0892327760299634\n"
                   "1000.000001 1000.400005 1 0 0 0 0 0\n"
                   "1000.101002 1000.200003 1 0 0 0 0 0\n"
                   "2000 2001 1 0 0 0 0 0\n");
  auto r = run("eval relations " + est + " --relations " + rel);
  expectExit(r, 0,
             {"3 of 6 relations used", "E = relation^-1 * (estimate(t1)^-1 * estimate(t2))",
              "Not used: 1 with no estimate pose at t1, 1 none at t2, 1 none at either",
              "| translation (m) | 0.050000 | 0.050000 |",
              "| rotation (deg) | 1.666667 | 1.527525 |", "| rotation² (deg²) | 4.333333 |"});
  r = run("eval relations " + est + " --relations " + rel + " --format json");
  expectExit(r, 0, {"\"used\": 3", "\"missing_t1\": 1"});
}

TEST_F(Cli, EveryShippedConfigValidates) {
  const fs::path configs = fs::path(plugslam::testing::sourceDir()) / "configs";
  int seen = 0;
  for (const auto& entry : fs::directory_iterator(configs)) {
    if (entry.path().extension() != ".yaml") continue;
    ++seen;
    // From a folder of the test's own, not the repository root: the configs name their data as
    // ${PLUGSLAM_DATA} (item 17.30).
    auto r = run("validate " + entry.path().string(),
                 "cd " + dir_.string() + " && PLUGSLAM_DATA=" + plugslam::testing::dataDir());
    if (r.out.find("cannot open") != std::string::npos ||
        r.out.find("does not exist") != std::string::npos)
      continue;  // a config's data is not on this machine
    EXPECT_EQ(r.code, 0) << entry.path() << "\n" << r.out;
  }
  EXPECT_GE(seen, 6);
}

// Item 17.1: bare `plugslam` (and with a global option) runs the default pipeline into out/,
// and --help says so; it once registered its logger twice and died.
TEST_F(Cli, NoCommandRunsTheDefaultPipeline) {
  auto r = run("-q", "cd " + dir_.string() + " &&");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("already exists"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "trajectory.tum")) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "session" / "session.yaml")) << r.out;
  r = run("--help");
  expectHas(r.out, "With no command, runs the built-in default pipeline");
}

// Item 17.13: the top-level help fits 100 columns; optimize lists its choices as eval does.
TEST_F(Cli, HelpIsShortAndListsChoices) {
  auto r = run("--help");
  std::istringstream lines(r.out);
  for (std::string line; std::getline(lines, line);)
    EXPECT_LE(line.size(), 100u) << "too long a help line: " << line;
  r = run("optimize --help");
  expectExit(r, 0,
             {"--solver TEXT:{gn,lm}", "--init TEXT:{file,odometry,chordal,best}",
              "--factorization TEXT:{auto,supernodal,simplicial,block}",
              "VERTEX_SE3:QUAT"});  // the formats moved to the command's own help
  r = run("optimize x.g2o --solver newton");
  EXPECT_EQ(r.code, 2) << r.out;
}

// Item 17.12: `config TYPE` prints the defaults, its only mode; --defaults is still accepted.
// Item 17.19: `describe run` shows the top-level keys of a config file.
TEST_F(Cli, ConfigNeedsNoFlagAndDescribeShowsTheTopLevel) {
  const std::string env = "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins";
  auto r = run("config fixture.CountingSource", env);
  expectExit(r, 0, {"frames: 10"});
  r = run("describe run");
  EXPECT_EQ(r.code, 0) << r.out;
  for (auto key : {"plugins", "source", "pipeline", "outputs", "max_frames", "on_module_error"})
    expectHas(r.out, std::string("  ") + key + " ");
}

// Issue 43: a shipped variant holds only what differs from its base; `config --resolved` prints
// the whole document its run uses (what its session saves), --set applied.
TEST_F(Cli, ConfigResolvedPrintsTheDocumentARunUses) {
  const std::string variant = plugslam::testing::sourceDir() + "/configs/sim3d_stereo_slam.yaml";
  auto r = run("config --resolved " + variant + " --set pipeline.graph.deterministic=true");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("base:"), std::string::npos) << r.out;
  expectHasAll(r.out, {"source: {type: sim.Simulator3D, world: street, camera: stereo, seed: 0}",
                       "align_previous_map: true",  // from sim3d_stereo.yaml
                       "{type: sdk.AppearanceDetector, scene: landmarks, min_travel: 50.0}",
                       "deterministic: true",
                       "  - {type: sdk.LandmarkMapWriter}\n"});
  r = run("config");
  expectExit(r, 2, {"give either a TYPE (its defaults) or --resolved FILE"});
}

// Item 17.5: a --do that names no module or no action fails before the first frame (exit 2,
// nothing written), not after the whole run with a dangling line.
TEST_F(Cli, BadActionFailsBeforeTheRun) {
  auto out = dir_ / "out";
  auto r = run("run " + config() + " -o " + out.string() + " --do source.nosuch");
  expectExit(
      r, 2,
      {"--do source.nosuch: module 'source' (fixture.CountingSource) has no action 'nosuch'"});
  EXPECT_FALSE(fs::exists(out / "run.json")) << "the run started";
  r = run("run " + config() + " -o " + out.string() + " --do pipeline.graph.save_graph:x.g2o");
  expectExit(r, 2, {"no module 'pipeline.graph'"});
  EXPECT_FALSE(fs::exists(out / "run.json"));
}

// Item 17.11: a run whose pipeline has no tracker says that nothing was estimated (no "0.0 Hz",
// no "0 loops"), and writes no empty trajectory.
TEST_F(Cli, ARunWithoutATrackerSaysSo) {
  auto cfg = write("plain.yaml", "plugins: [" + buildDir() + "/tests/plugins/plugslam_fixture.so, io]\n"
                                 "source: {type: fixture.CountingSource, frames: 5}\n"
                                 "outputs: [io.TrajectoryWriter]\n");
  auto out = dir_ / "out";
  auto r = run("run " + cfg + " -o " + out.string());
  expectExit(r, 0, {"5 frames in", "the pipeline has no tracker, so no pose was estimated"});
  EXPECT_EQ(r.out.find("pipeline alone"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("loops closed"), std::string::npos) << r.out;
  expectHas(r.out, "trajectory.tum not written");
  EXPECT_FALSE(fs::exists(out / "trajectory.tum"));
  EXPECT_FALSE(fs::exists(out / "session")) << "no tracker, no maps: no session";
}

// Item 17.14: every run with a tracker leaves OUTDIR/session, the final one (the mid-run
// checkpoint is removed), and README's `run --session OUTDIR/session` works after it.
// Item 17.10: a run too short for RPE over 1 m says so instead of printing nan.
TEST_F(Cli, EveryRunSavesItsSessionAndShortRunsHaveNoRpe) {
  auto out = dir_ / "out";
  auto r = run("run -o " + out.string() + " --set max_frames=15 --checkpoint-every 0.000001");
  expectExit(r, 0, {"session saved in " + (out / "session").string()});
  EXPECT_TRUE(fs::exists(out / "session" / "session.yaml"));
  EXPECT_FALSE(fs::exists(out / "checkpoint")) << "the stale checkpoint stayed";
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  expectHas(r.out, "no RPE(1 m): the run is too short for it (the reference path is");
  auto out2 = dir_ / "out2";
  r = run("run --session " + (out / "session").string() + " -o " + out2.string() +
          " --set max_frames=20");
  expectExit(r, 0, {"(mapping)"});
}

// Items 17.2, 17.3, 17.4 on a terminal: the progress counts to max_frames, log lines never land
// on the progress line (it is erased first and drawn again after), and the final work shows.
TEST_F(Cli, ProgressOnATerminal) {
  auto cfg = config("on_module_error: skip\n");
  const auto r = runOnTerminal({"run", cfg, "-o", (dir_ / "out").string(), "--set", "max_frames=7",
                                "--set", "pipeline.preprocessors[0].fail_at=3"},
                               dir_);
  expectExit(r, 0, {"frame 1/7"});  // max_frames bounds the 20 frames of the source
  EXPECT_EQ(r.out.find("/20"), std::string::npos) << r.out;
  expectHas(r.out, "frame 3 skipped (on_module_error: skip)");
  expectLogLinesStartClean(r.out);
  // After the log line the progress line comes back.
  const auto warned = r.out.find("frame 3 skipped");
  ASSERT_NE(warned, std::string::npos);
  EXPECT_NE(r.out.find("\r  frame 1/7", warned), std::string::npos) << r.out;
  expectHas(r.out, "finishing: final loop passes");
  expectHas(r.out, "7 frames in");
}

// Item 17.30: a config's ${PLUGSLAM_DATA} is the data folder, from the environment when the run
// starts, so the shipped real-data configs work from any folder; other variables are errors.
TEST_F(Cli, ConfigsFindTheDataFolderFromAnyFolder) {
  const std::string carmen = plugslam::testing::sourceDir() + "/configs/laser2d_carmen.yaml";
  auto r = run("validate " + carmen, "cd " + dir_.string() + " && PLUGSLAM_DATA=/no/such/folder");
  expectExit(r, 2, {"/no/such/folder/laser2d/intel-gfs-corrected/intel-corrected.log.gz"});
  auto bad =
      fixtureConfig("bad.yaml", "source: {type: fixture.CountingSource, sensor: '${HOME}/x'}\n");
  r = run("validate " + bad);
  expectExit(r, 2, {bad + ":2:48: unknown variable '${HOME}': a config knows ${PLUGSLAM_DATA}"});
  const std::string data = plugslam::testing::dataDir();
  if (!fs::exists(data + "/laser2d/intel-gfs-corrected/intel-corrected.log.gz"))
    GTEST_SKIP() << "no intel log under " << data << " (set PLUGSLAM_DATA)";
  r = run("validate " + carmen, "cd " + dir_.string() + " && PLUGSLAM_DATA=" + data);
  EXPECT_EQ(r.code, 0) << r.out;
}
