// The plugslam CLI as a user runs it: output, exit codes (0 ok, 1 runtime failure, 2 bad input).
#include <gtest/gtest.h>

#include "test_paths.h"
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "plugslam/version.h"

namespace fs = std::filesystem;

namespace {

std::string buildDir() { return plugslam::testing::buildDir(); }

struct Result {
  int code;
  std::string out;
};

Result run(const std::string& args, const std::string& env = "") {
  std::string cmd = env + " " + buildDir() + "/bin/plugslam " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  std::string out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("plugslam_cli_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  std::string config(const std::string& extra = "") {
    return write("run.yaml", "plugins: [" + buildDir() + "/tests/plugins/plugslam_fixture.so]\n" +
                                 "source: {type: fixture.CountingSource, frames: 20}\n"
                                 "pipeline:\n  preprocessors:\n    - {type: fixture.Scale, factor: 0.5}\n"
                                 "outputs: [fixture.SumWriter]\n" + extra);
  }
  fs::path dir_;
};

void expectHas(const std::string& s, const std::string& part) {
  EXPECT_NE(s.find(part), std::string::npos) << "'" << part << "' not in:\n" << s;
}

}  // namespace

TEST_F(Cli, VersionAndHelp) {
  auto r = run("--version");
  EXPECT_EQ(r.code, 0);
  expectHas(r.out, std::string("plugslam ") + PLUGSLAM_VERSION_STRING + " (plugin ABI " +
                       std::to_string(PLUGSLAM_ABI_MAJOR) + "." +
                       std::to_string(PLUGSLAM_ABI_MINOR) + ")");
  r = run("--help");
  EXPECT_EQ(r.code, 0);
  for (auto c : {"plugins", "describe", "config", "validate", "run", "reference"}) expectHas(r.out, c);
  r = run("frobnicate");
  EXPECT_EQ(r.code, 2);
}

TEST_F(Cli, PluginsListsTypesAndRefusals) {
  auto r = run("plugins", "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins/bad:" + buildDir() +
                              "/tests/plugins");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "sdk.Pipeline");
  expectHas(r.out, "fixture.CountingSource");
  expectHas(r.out, "refused: plugin 'wrongabi'");
  expectHas(r.out, "refused: plugin 'wrongfingerprint'");
}

TEST_F(Cli, DescribeAndDefaults) {
  auto r = run("describe fixture.Scale", "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "fixture.Scale (PreProcessor, plugin fixture)");
  expectHas(r.out, "factor");
  expectHas(r.out, "default 2");
  r = run("describe sdk.Pipelin");
  EXPECT_EQ(r.code, 2);
  expectHas(r.out, "did you mean 'sdk.Pipeline'?");
  r = run("config --defaults fixture.CountingSource",
          "PLUGSLAM_PLUGIN_PATH=" + buildDir() + "/tests/plugins");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "type: fixture.CountingSource");
  expectHas(r.out, "frames: 10");
}

TEST_F(Cli, ValidateGoodAndBroken) {
  auto good = config();
  auto r = run("validate " + good);
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "OK");
  auto bad = write("bad.yaml", "plugins: [" + buildDir() +
                                   "/tests/plugins/plugslam_fixture.so]\n"
                                   "source: {type: fixture.CountingSource, frams: 3}\n");
  r = run("validate " + bad);
  EXPECT_EQ(r.code, 2);
  expectHas(r.out, bad + ":2:40: source.frams: unknown key 'frams'");
  expectHas(r.out, "did you mean 'frames'?");
  r = run("validate " + good + " --set pipeline.preprocessors[0].factor=abc");
  EXPECT_EQ(r.code, 2);
  expectHas(r.out, "--set pipeline.preprocessors[0].factor=abc: pipeline.preprocessors[0].factor: expected a number");
  r = run("validate " + (dir_ / "missing.yaml").string());
  EXPECT_EQ(r.code, 2);
  expectHas(r.out, "cannot open config file");
}

// Item 17.31: validate lists every error of the file, each on its own line with file:line:column
// and the key path, then a count; the missing source is one of them, not a later surprise.
TEST_F(Cli, ValidateReportsEveryError) {
  auto bad = write("bad.yaml", "plugins: [" + buildDir() +
                                   "/tests/plugins/plugslam_fixture.so]\n"
                                   "pipeline:\n"
                                   "  preprocessors:\n"
                                   "    - {type: fixture.Scale, factr: 0.5}\n"
                                   "    - {type: fixture.Scale, factor: abc}\n"
                                   "outputs: [fixture.SumWritr]\n");
  auto r = run("validate " + bad);
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, "[error] " + bad + ":1:1: source: missing 'source:'");
  expectHas(r.out, "[error] " + bad + ":4:29: pipeline.preprocessors[0].factr: unknown key 'factr'");
  expectHas(r.out, "[error] " + bad + ":5:37: pipeline.preprocessors[1].factor: expected a number");
  expectHas(r.out, "[error] " + bad + ":6:11: outputs[0]: unknown type 'fixture.SumWritr'");
  expectHas(r.out, "[error] 4 errors in " + bad);
}

// Item 17.6: validate checks the wiring of the entries: a slice's measurement that no
// preprocessor writes, a scene entry no tracker slice writes (also for the back-end's slices,
// whose measurement is a local map's scene), a preprocessor input the source does not provide.
// Each error names where (the file's line and column, or the --set), the key path and a
// did-you-mean.
TEST_F(Cli, ValidateChecksTheEntryWiring) {
  const std::string shipped = plugslam::testing::sourceDir() + "/configs/default.yaml";
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
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, bad + ":5:47: pipeline.preprocessors[0].input: the source (sim.Simulator2D) "
                         "provides no raw entry 'front_lasr' (plugslam::LaserScan); did you mean "
                         "'front_laser'?; it provides: front_laser, ground_truth, odom, rear_laser");
  expectHas(r.out, bad + ":11:71: pipeline.tracker.aligner.slices[0].scene: no tracker slice "
                         "writes scene entry 'frnt' (laser2d.PointCloud2D); did you mean 'front'?");
  expectHas(r.out, bad + ":20:66: pipeline.graph.validators[0].aligner.slices[0].measurement: no "
                         "tracker slice writes scene entry 'rear' (in the back-end a slice's "
                         "measurement is a local map's scene)");
  expectHas(r.out, "3 errors in " + bad);
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
  EXPECT_EQ(r.code, 1) << r.out;
  expectHas(r.out, "module 'source' (fixture.CountingSource) failed: fixture failure at frame 3");
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
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "rmse");
  r = run("eval ate " + ref + " " + est + " --align none --format json");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "\"rmse\"");
  r = run("eval rpe " + ref + " " + est + " --unit frames --delta 1 --format json");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "0.1");  // every step is 0.1 m too long
  r = run("eval relations " + est + " --reference " + ref + " --max-distance 2");
  EXPECT_EQ(r.code, 0) << r.out;
  auto late = write("late.tum", tum(1000, 1.0, 5));
  r = run("eval ate " + ref + " " + late);
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, "no overlap");
  auto bad = write("bad.tum", "0 1 2 3\n");
  r = run("eval ate " + ref + " " + bad);
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, "bad.tum:1");
}

TEST_F(Cli, EveryShippedConfigValidates) {
  const fs::path configs = fs::path(plugslam::testing::sourceDir()) / "configs";
  int seen = 0;
  for (const auto& entry : fs::directory_iterator(configs)) {
    if (entry.path().extension() != ".yaml") continue;
    ++seen;
    // From the repository root, as the configs' relative data paths expect.
    auto r = run("validate " + entry.path().string(),
                 "cd " + plugslam::testing::sourceDir() + " &&");
    if (r.out.find("cannot open") != std::string::npos ||
        r.out.find("does not exist") != std::string::npos)
      continue;  // a config pointing at ../shared/data on a machine without it
    EXPECT_EQ(r.code, 0) << entry.path() << "\n" << r.out;
  }
  EXPECT_GE(seen, 6);
}
