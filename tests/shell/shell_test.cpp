// `plugslam shell` as a user drives it, through scripts on stdin: every command, errors that
// leave the shell alive, hot swap of a slice type, reload of a rebuilt plugin, save/load with
// the same optimization result, and an interrupted `plugslam run` that leaves a loadable session.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <optional>

#include "run_command.h"
#include "test_paths.h"
#include "temp_dir.h"

namespace fs = std::filesystem;

namespace {

std::string bin() { return plugslam::testing::buildDir() + "/bin/plugslam"; }
std::string pluginDir() { return plugslam::testing::buildDir() + "/tests/plugins"; }

using Result = plugslam::testing::CommandResult;

Result sh(const std::string& cmd) {
  return plugslam::testing::runCommand(cmd);
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

size_t count(const std::string& s, const std::string& part) {
  size_t n = 0;
  for (size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
  return n;
}

void expectHas(const std::string& s, const std::string& part) {
  EXPECT_NE(s.find(part), std::string::npos) << "'" << part << "' not in:\n" << s;
}

class ShellTest : public ::testing::Test {
 protected:
  void SetUp() override {
    tmp_.emplace("plugslam_shell");  // a fresh folder of this test's own
    dir_ = tmp_->path();
  }
  void TearDown() override { tmp_.reset(); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) {
    return tmp_->write(name, text);  // checked
  }
  // The lmsim pipeline (tests/shell/lmsim.yaml) with `laps` laps.
  std::string lmsimConfig(double laps) {
    std::string text = readFile(plugslam::testing::sourceDir() + "/tests/shell/lmsim.yaml");
    text.replace(text.find("laps: 2}"), 8, "laps: " + std::to_string(laps) + "}");
    return write("lmsim.yaml", text);
  }
  // Runs a shell script fed through stdin.
  Result shell(const std::string& script) {
    write("script.txt", script);
    return sh("PLUGSLAM_PLUGIN_PATH=" + pluginDir() + " " + bin() + " shell -o " + path("out") +
              " < " + path("script.txt"));
  }
  std::optional<plugslam::testing::TempDir> tmp_;
  fs::path dir_;
};

}  // namespace

TEST_F(ShellTest, EveryCommandThroughStdin) {
  const std::string cfg = lmsimConfig(2);
  const std::string slice = "pipeline.tracker.aligner.slices[0]";
  Result r = shell(
      "help\n"
      "load " +
      cfg +
      "\n"
      "validate\n"
      "plugins\n"
      "list actions\n"
      "get " +
      slice +
      ".sigma\n"
      "set " +
      slice +
      ".sigma 0.03\n"
      "get " +
      slice +
      ".sigma\n"
      "set source.delay 0.001\n"  // 0.4 s per run: pause lands mid-run
      "step 5\n"
      "status\n"
      "step 10\n"
      "do pipeline.tracker.reset\n"
      "resume\n"
      "pause\n"
      "status\n"
      "stop\n"
      "run\n"
      "wait\n"
      "status\n"
      "save " +
      path("s1") +
      "\n"
      "do pipeline.graph.optimize_now\n"
      "do pipeline.graph.save_graph " +
      path("g1.g2o") +
      "\n"
      "load-session " +
      path("s1") +
      "\n"
      "status\n"
      "do pipeline.graph.optimize_now\n"
      "do pipeline.graph.save_graph " +
      path("g2.g2o") +
      "\n"
      "swap " +
      slice +
      " lmsim.WeightedLandmarkSlice\n"
      "get " +
      slice +
      "\n"
      "load " +
      cfg +
      "\n"
      "swap " +
      slice +
      " lmsim.WeightedLandmarkSlice\n"
      "run\n"
      "wait\n"
      "reload lmsim\n"
      "get " +
      slice +
      ".weight\n"
      "quit\n"
      "status\n");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "load-session DIR [--localize]");
  expectHas(r.out, ": OK (");
  expectHas(r.out, "lmsim 1.0.0");
  expectHas(r.out, "pipeline.graph.optimize_now");
  expectHas(r.out, "pipeline.graph.save_graph");
  expectHas(r.out, "pipeline.tracker.reset");
  expectHas(r.out, slice + ".sigma = 0.02 (double, m)");
  expectHas(r.out, slice + ".sigma = 0.03");
  expectHas(r.out, "paused at frame 5");
  expectHas(r.out, "state: paused, frame 5/");
  expectHas(r.out, "paused at frame 15");
  expectHas(r.out, "tracker reset; the next frame starts local map");
  expectHas(r.out, "resumed");
  expectHas(r.out, "run finished (stopped)");
  expectHas(r.out, "run finished (end of data)");
  // Item 17.16: the shell names the reference entry as the CLI does, not "ground truth".
  expectHas(r.out, "against 'ground_truth': ATE rmse");
  EXPECT_EQ(r.out.find("against ground truth"), std::string::npos);
  expectHas(r.out, "state: finished");
  expectHas(r.out, "saved session " + path("s1"));
  expectHas(r.out, "loaded session " + path("s1"));
  expectHas(r.out, "mapping: new maps are appended");
  expectHas(r.out, slice + ": lmsim.LandmarkSlice -> lmsim.WeightedLandmarkSlice (dropped: sigma)");
  expectHas(r.out, "type: lmsim.WeightedLandmarkSlice");
  expectHas(r.out, "reloaded lmsim 1.0.0");
  expectHas(r.out, slice + ".weight = 2500");
  EXPECT_EQ(count(r.out, "error:"), 0u) << r.out;
  // Loops were closed on the second lap.
  const auto done = r.out.find("run finished (end of data)");
  ASSERT_NE(done, std::string::npos);
  const std::string line = r.out.substr(done, r.out.find('\n', done) - done);
  EXPECT_EQ(line.find(" 0 loops closed"), std::string::npos) << line;
  // Saved then loaded: the same optimization, to the bit (the g2o text prints every digit).
  const std::string g1 = readFile(path("g1.g2o")), g2 = readFile(path("g2.g2o"));
  EXPECT_FALSE(g1.empty());
  EXPECT_EQ(g1, g2);
  for (const char* f : {"session.yaml", "config.yaml", "maps.bin", "graph.g2o", "trajectory.tum"})
    EXPECT_TRUE(fs::exists(dir_ / "s1" / f)) << f;
  // Nothing after quit ran.
  EXPECT_EQ(r.out.find("> status", r.out.find("> quit")), std::string::npos);
}

// `rate R` paces the shell's runs by the frames' stamps (lmsim: 10 Hz): 11 frames are 1.0 s of
// data, so at rate 2 `step 11` takes at least 0.5 s (a lower bound: the pacing only waits).
TEST_F(ShellTest, RatePacesTheRunByItsStamps) {
  const std::string cfg = lmsimConfig(0.3);
  const auto start = std::chrono::steady_clock::now();
  Result r = shell("load " + cfg + "\nrate\nrate 2\nrate\nstep 11\nrate -1\nrate fast\nrate 0\nstop\n");
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.code, 1) << r.out;  // two bad rates
  expectHas(r.out, "rate 0 (as fast as possible)");
  expectHas(r.out, "> rate\nrate 2\n");
  expectHas(r.out, "paused at frame 11");
  expectHas(r.out, "error: rate: expected a number >= 0");
  expectHas(r.out, "got 'fast'");
  EXPECT_EQ(count(r.out, "error:"), 2u) << r.out;
  EXPECT_GE(wall, 0.5) << r.out;
}

TEST_F(ShellTest, ErrorsLeaveTheShellAliveAndTheStateIntact) {
  const std::string cfg = lmsimConfig(0.3);
  const std::string slice = "pipeline.tracker.aligner.slices[0]";
  Result r = shell(
      "frobnicate\n"
      "get pipeline\n"
      "load /nonexistent/config.yaml\n"
      "load " +
      cfg +
      "\n"
      "set source.laps -1\n"
      "set " +
      slice +
      ".sigmaa 1\n"
      "get " +
      slice +
      ".sigma\n"
      "get source.laps\n"
      "get pipeline.nope\n"
      "get pipeline.tracker.aligner.slices[3]\n"
      "do pipeline.graph.nope\n"
      "do nomodule.act\n"
      "swap " +
      slice +
      " sdk.DistanceSplitter\n"
      "swap " +
      slice +
      " lmsim.NoSuchSlice\n"
      "step 0\n"
      "step abc\n"
      "pause\n"
      "resume\n"
      "load-session /nonexistent\n"
      "reload nosuch\n"
      "step 2\n"
      "set " +
      slice +
      ".sigma 0.05\n"
      "run\n"
      "stop\n"
      "validate\n"
      "get " +
      slice +
      ".sigma\n"
      "run\n"
      "wait\n");
  EXPECT_EQ(r.code, 1) << r.out;  // a script with failing commands
  expectHas(r.out, "error: unknown command 'frobnicate'");
  expectHas(r.out, "error: no config loaded (load CONFIG)");
  expectHas(r.out, "error: cannot open config file '/nonexistent/config.yaml'");
  expectHas(r.out, "error: set source.laps -1: source.laps: ");  // what was typed, not --set
  expectHas(r.out, "did you mean 'sigma'?");
  expectHas(r.out, "error: no parameter or module 'nope'");
  expectHas(r.out, "the list has 1 modules");
  expectHas(r.out, "has no action 'nope'");
  expectHas(r.out, "error: no module 'nomodule'");
  expectHas(r.out,
            "'sdk.DistanceSplitter' is a Splitter, but '" + slice + "' takes an AlignerSlice2D");
  expectHas(r.out, "error: unknown type 'lmsim.NoSuchSlice'");
  expectHas(r.out, "error: expected a positive number of frames, got '0'");
  expectHas(r.out, "error: no run in progress");
  expectHas(r.out, "error: no paused run");
  expectHas(r.out, "error: session folder '/nonexistent' does not exist");
  expectHas(r.out, "error: plugin 'nosuch' is not loaded");
  expectHas(r.out, "error: cannot change parameters while a run is in progress");
  expectHas(r.out, "error: a run is paused");
  // After all that the config is intact and runs.
  expectHas(r.out, slice + ".sigma = 0.02 (double, m)");
  expectHas(r.out, "source.laps = 0.3 (double)");
  expectHas(r.out, ": OK (");
  expectHas(r.out, "run finished (end of data)");
  EXPECT_EQ(count(r.out, "error:"), 19u) << r.out;
}

TEST_F(ShellTest, ReloadPicksUpARebuiltPluginFromTheShell) {
  // The fixture plugin copied into a folder the test controls, then replaced by its v2 build
  // (renamed over it, as a build does) while the shell runs.
  const std::string so = path("plugslam_fixture.so");
  fs::copy_file(pluginDir() + "/plugslam_fixture.so", so);
  const std::string cfg = write(
      "fixture.yaml", "plugins: [" + so +
                          "]\n"
                          "source: {type: fixture.CountingSource, frames: 20}\n"
                          "pipeline:\n  preprocessors:\n    - {type: fixture.Scale, factor: 0.5}\n"
                          "outputs: [fixture.SumWriter]\n");
  const std::string log = path("shell.log");
  FILE* in = popen((bin() + " shell -o " + path("out") + " > " + log + " 2>&1").c_str(), "w");
  ASSERT_NE(in, nullptr);
  std::fputs(("load " + cfg + "\ndo pipeline.preprocessors[0].behaviour\nrun\nwait\n").c_str(), in);
  std::fflush(in);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (readFile(log).find("run finished") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const std::string first_sum = readFile(path("out/sum.txt"));
  fs::copy_file(pluginDir() + "/v2/plugslam_fixture.so", path("new.so"));
  fs::rename(path("new.so"), so);
  std::fputs("reload fixture\ndo pipeline.preprocessors[0].behaviour\nrun\nwait\nplugins\nquit\n",
             in);
  const int status = pclose(in);
  const std::string out = readFile(log);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << out;
  EXPECT_EQ(first_sum, "20 95\n");
  EXPECT_EQ(readFile(path("out/sum.txt")), "20 190\n") << out;
  const auto one = out.find("> do pipeline.preprocessors[0].behaviour\n1\n");
  const auto two = out.find("> do pipeline.preprocessors[0].behaviour\n2\n");
  EXPECT_NE(one, std::string::npos) << out;
  EXPECT_NE(two, std::string::npos) << out;
  EXPECT_LT(one, two);
  expectHas(out, "reloaded fixture 1.0.0 from " + so);
  EXPECT_EQ(count(out, "error:"), 0u) << out;
}

TEST_F(ShellTest, LocalizationOnlyFromTheShell) {
  const std::string cfg = lmsimConfig(2);
  Result r = shell("load " + cfg + "\nrun\nwait\nsave " + path("s") +
                   "\nstatus\n"
                   "load-session " +
                   path("s") +
                   " --localize\n"
                   "set source.laps 1\n"
                   "run\nwait\nstatus\n");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "localization: the maps are frozen");
  expectHas(r.out, "running " + path("s") + "/config.yaml (localization)");
  // The graph is the saved one, unchanged by the localization run.
  const auto first = r.out.find("> status\n");
  const auto second = r.out.rfind("> status\n");
  ASSERT_NE(first, second);
  auto graphOf = [&](size_t at) {
    const auto g = r.out.find("graph ", at);
    return r.out.substr(g, r.out.find(',', g) - g);
  };
  EXPECT_EQ(graphOf(first), graphOf(second)) << r.out;
  expectHas(r.out, "local maps 0, tracking failures 0");
}

TEST_F(ShellTest, RunDoesActionsAfterTheRun) {
  const std::string cfg = lmsimConfig(0.5);
  Result r = sh("PLUGSLAM_PLUGIN_PATH=" + pluginDir() + " " + bin() + " run " + cfg + " -o " +
                path("out") + " --do pipeline.graph.save_graph:" + path("g.g2o") +
                " --do pipeline.graph.optimize_now");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "loops closed");
  expectHas(r.out, "pipeline.graph.save_graph: wrote");
  EXPECT_NE(readFile(path("g.g2o")).find("VERTEX_SE2"), std::string::npos);
  r = sh(bin() + " run " + cfg + " --localize");
  EXPECT_EQ(r.code, 2) << r.out;
  expectHas(r.out, "--localize needs --session DIR");
}

TEST_F(ShellTest, InterruptedRunLeavesALoadableSession) {
  const std::string cfg = lmsimConfig(100);
  const std::string out = path("out");
  // 1 ms per frame: the run lasts 20 s unless interrupted.
  {
    std::string text = readFile(cfg);
    text.replace(text.find("laps: "), 6, "delay: 0.001, laps: ");
    std::ofstream(cfg) << text;
  }
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("PLUGSLAM_PLUGIN_PATH", pluginDir().c_str(), 1);
    const std::string log = path("run.log");
    FILE* f = std::freopen(log.c_str(), "w", stdout);
    (void)f;
    dup2(fileno(stdout), 2);
    execl(bin().c_str(), "plugslam", "run", cfg.c_str(), "-o", out.c_str(), nullptr);
    _exit(127);
  }
  // Wait until the run is under way (its log says so), then Ctrl-C.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (readFile(path("run.log")).find("running ") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  const std::string log = readFile(path("run.log"));
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 130) << log;
  // Saved once before the run finishes (a second Ctrl-C during a long final optimization keeps
  // it), then again with the final optimization.
  expectHas(log, "interrupted: session saved in " + out + "/session");
  expectHas(log, "Ctrl-C again quits now");
  expectHas(log, "interrupted at frame");
  expectHas(log, "session saved in " + out + "/session");
  // Item 17.15: --session adds a new run to the session; the message does not call it a resume.
  expectHas(log, "It is not a point to resume from: `plugslam run CONFIG --session " + out +
                     "/session` adds a new run's maps to it");
  EXPECT_EQ(log.find("continue with"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out + "/session.new")) << "the atomic save left its copy";
  EXPECT_NE(readFile(out + "/run.json").find("\"stopped_by\": \"interrupted\""), std::string::npos);
  // The session loads and a run extends it.
  Result r = sh("PLUGSLAM_PLUGIN_PATH=" + pluginDir() + " " + bin() + " run --session " + out +
                "/session --set source.laps=0.5 -o " + path("out2"));
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "frames in");
  r = shell("load-session " + out + "/session\nstatus\n");
  EXPECT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "loaded session " + out + "/session");
}
