// `plugslam shell` as a user drives it, through scripts on stdin: every command, errors that
// leave the shell alive, hot swap of a slice type, reload of a rebuilt plugin, save/load with
// the same optimization result, and an interrupted `plugslam run` that leaves a loadable session.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <optional>
#include <string>

#include "run_command.h"
#include "test_paths.h"
#include "temp_dir.h"

namespace fs = std::filesystem;

namespace {

std::string bin() { return plugslam::testing::buildDir() + "/bin/plugslam"; }
std::string pluginDir() { return plugslam::testing::buildDir() + "/tests/plugins"; }

using Result = plugslam::testing::CommandResult;
using plugslam::testing::expectHas;
using plugslam::testing::expectHasAll;

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

// A command with its input and its output (stdout and stderr) on pipes: the test reads what it
// prints as it prints it, so it acts when the command has done something, not after a while.
class Process {
 public:
  explicit Process(const std::string& cmd) {
    ::signal(SIGPIPE, SIG_IGN);  // a command that died fails the test, not kills it
    int in[2], out[2];
    if (pipe(in) != 0 || pipe(out) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      dup2(in[0], 0);
      dup2(out[1], 1);
      dup2(out[1], 2);
      for (int fd : {in[0], in[1], out[0], out[1]}) close(fd);
      execl("/bin/sh", "sh", "-c", cmd.c_str(), nullptr);
      _exit(127);
    }
    close(in[0]);
    close(out[1]);
    in_ = in[1];
    out_ = out[0];
  }
  ~Process() { finish(); }
  void send(const std::string& text) {
    for (size_t at = 0; at < text.size();) {
      const ssize_t n = write(in_, text.data() + at, text.size() - at);
      if (n <= 0) return;
      at += static_cast<size_t>(n);
    }
  }
  /// Reads until the output holds `text` (true) or the command closed it (false).
  bool readUntil(const std::string& text) {
    char buf[4096];
    while (output_.find(text) == std::string::npos) {
      const ssize_t n = read(out_, buf, sizeof buf);
      if (n <= 0) return false;
      output_.append(buf, static_cast<size_t>(n));
    }
    return true;
  }
  /// Closes the command's input, reads the rest of its output and returns its exit code (-1 when
  /// it did not exit normally).
  int finish() {
    if (pid_ <= 0) return -1;
    close(in_);
    char buf[4096];
    for (ssize_t n; (n = read(out_, buf, sizeof buf)) > 0;)
      output_.append(buf, static_cast<size_t>(n));
    close(out_);
    int status = 0;
    waitpid(pid_, &status, 0);
    pid_ = -1;
    code_ = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return code_;
  }
  const std::string& output() const { return output_; }

 private:
  pid_t pid_ = -1;
  int in_ = -1, out_ = -1, code_ = -1;
  std::string output_;
};

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
      "set source.endless true\n"  // the pause lands mid-run, whatever the machine's speed
      "step 5\n"
      "status\n"
      "step 10\n"
      "do pipeline.tracker.reset\n"
      "resume\n"
      "pause\n"
      "status\n"
      "stop\n"
      "set source.endless false\n"
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
  expectExit(
      r, 0,
      {"load-session DIR [--localize]", ": OK (", "lmsim 1.0.0", "pipeline.graph.optimize_now",
       "pipeline.graph.save_graph", "pipeline.tracker.reset", slice + ".sigma = 0.02 (double, m)",
       slice + ".sigma = 0.03", "paused at frame 5", "state: paused, frame 5, ",
       "paused at frame 15", "tracker reset; the next frame starts local map", "resumed",
       "run finished (stopped)", "run finished (end of data)"});
  // Item 17.16: the shell names the reference entry as the CLI does, not "ground truth".
  expectHas(r.out, "against 'ground_truth': ATE rmse");
  EXPECT_EQ(r.out.find("against ground truth"), std::string::npos);
  // An endless source has no size to show progress against; the lapping one has.
  expectHasAll(r.out, {"state: finished, frame 403/403 (100.0%)",
                       "saved session " + path("s1"),
                       "loaded session " + path("s1"),
                       "mapping: new maps are appended",
                       slice +
                           ": lmsim.LandmarkSlice -> lmsim.WeightedLandmarkSlice (dropped: sigma)",
                       "type: lmsim.WeightedLandmarkSlice",
                       "reloaded lmsim 1.0.0",
                       slice + ".weight = 2500"});
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

// `rate R` paces the shell's runs by the frames' stamps (lmsim: 10 Hz; at rate 2 `step 11` is
// 0.5 s of waits). What is asserted is what the shell says: the schedule itself is
// playback_test's, which records the waits instead of timing a run.
TEST_F(ShellTest, RateSetsThePlaybackRate) {
  const std::string cfg = lmsimConfig(0.3);
  Result r = shell("load " + cfg + "\nrate\nrate 2\nrate\nstep 11\nrate -1\nrate fast\nrate 0\nstop\n");
  EXPECT_EQ(r.code, 1) << r.out;  // two bad rates
  expectHasAll(r.out, {"rate 0 (as fast as possible)",
                       "> rate\nrate 2\n",
                       "paused at frame 11",
                       "error: rate: expected a number >= 0",
                       "got 'fast'"});
  EXPECT_EQ(count(r.out, "error:"), 2u) << r.out;
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
  expectHasAll(r.out, {"error: unknown command 'frobnicate'",
                       "error: no config loaded (load CONFIG)",
                       "error: cannot open config file '/nonexistent/config.yaml'",
                       "error: set source.laps -1: source.laps: ",  // what was typed, not --set
                       "did you mean 'sigma'?",
                       "error: no parameter or module 'nope'",
                       "the list has 1 modules",
                       "has no action 'nope'",
                       "error: no module 'nomodule'"});
  expectHas(r.out,
            "'sdk.DistanceSplitter' is a Splitter, but '" + slice + "' takes an AlignerSlice2D");
  expectHasAll(r.out, {"error: unknown type 'lmsim.NoSuchSlice'",
                       "error: expected a positive number of frames, got '0'",
                       "error: no run in progress",
                       "error: no paused run",
                       "error: session folder '/nonexistent' does not exist",
                       "error: plugin 'nosuch' is not loaded",
                       "error: cannot change parameters while a run is in progress",
                       "error: a run is paused"});
  // After all that the config is intact and runs.
  expectHasAll(r.out, {slice + ".sigma = 0.02 (double, m)",
                       "source.laps = 0.3 (double)",
                       ": OK (",
                       "run finished (end of data)"});
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
  Process proc("PLUGSLAM_PLUGIN_PATH=" + pluginDir() + " " + bin() + " shell -o " + path("out"));
  proc.send("load " + cfg + "\ndo pipeline.preprocessors[0].behaviour\nrun\nwait\n");
  // The first run is over (and wrote its sum) before the library is replaced.
  ASSERT_TRUE(proc.readUntil("run finished")) << proc.output();
  const std::string first_sum = readFile(path("out/sum.txt"));
  fs::copy_file(pluginDir() + "/v2/plugslam_fixture.so", path("new.so"));
  fs::rename(path("new.so"), so);
  proc.send("reload fixture\ndo pipeline.preprocessors[0].behaviour\nrun\nwait\nplugins\nquit\n");
  const int code = proc.finish();
  const std::string out = proc.output();
  EXPECT_EQ(code, 0) << out;
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
  expectExit(r, 0,
             {"localization: the maps are frozen",
              "running " + path("s") + "/config.yaml (localization)"});
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
  expectExit(r, 0, {"loops closed", "pipeline.graph.save_graph: wrote"});
  EXPECT_NE(readFile(path("g.g2o")).find("VERTEX_SE2"), std::string::npos);
  r = sh(bin() + " run " + cfg + " --localize");
  expectExit(r, 2, {"--localize needs --session DIR"});
}

TEST_F(ShellTest, InterruptedRunLeavesALoadableSession) {
  const std::string cfg = lmsimConfig(100);
  const std::string out = path("out");
  // 100 laps, interrupted when the source reads frame 200, as a Ctrl-C there would: the same
  // run on any machine, where a Ctrl-C sent after a while lands wherever the run got to.
  {
    std::string text = readFile(cfg);
    text.replace(text.find("laps: "), 6, "interrupt_at: 200, laps: ");
    std::ofstream(cfg) << text;
  }
  const Result run =
      sh("PLUGSLAM_PLUGIN_PATH=" + pluginDir() + " " + bin() + " run " + cfg + " -o " + out);
  const std::string& log = run.out;
  EXPECT_EQ(run.code, 130) << log;
  // Saved once before the run finishes (a second Ctrl-C during a long final optimization keeps
  // it), then again with the final optimization.
  expectHasAll(log, {"interrupted: session saved in " + out + "/session",
                     "Ctrl-C again quits now",
                     "interrupted at frame",
                     "session saved in " + out + "/session"});
  // Item 17.15: --session adds a new run to the session; the message does not call it a resume.
  expectHas(log, "It is not a point to resume from: `plugslam run CONFIG --session " + out +
                     "/session` adds a new run's maps to it");
  EXPECT_EQ(log.find("continue with"), std::string::npos) << log;
  EXPECT_FALSE(std::filesystem::exists(out + "/session.new")) << "the atomic save left its copy";
  EXPECT_NE(readFile(out + "/run.json").find("\"stopped_by\": \"interrupted\""), std::string::npos);
  // The session loads and a run extends it.
  Result r = sh("PLUGSLAM_PLUGIN_PATH=" + pluginDir() + " " + bin() + " run --session " + out +
                "/session --set source.laps=0.5 --set source.interrupt_at=-1 -o " + path("out2"));
  expectExit(r, 0, {"frames in"});
  r = shell("load-session " + out + "/session\nstatus\n");
  expectExit(r, 0, {"loaded session " + out + "/session"});
}
