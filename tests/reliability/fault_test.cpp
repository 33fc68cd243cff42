// Faults in plugin modules during a run: whatever a source, preprocessor or sink throws (a
// std::exception or anything else) is caught at the module boundary and reported with the
// module's path and type (plugin.Type); the process exits 1 without crashing. By policy
// (`on_module_error`) the run stops with its outputs and session saved, or skips the frame.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_paths.h"

namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Result {
  bool signalled = false;
  int code = -1;
  std::string out;
};

Result runCli(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> all{plugslam::testing::buildDir() + "/bin/plugslam"};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  Result r;
  r.signalled = WIFSIGNALED(status);
  if (WIFEXITED(status)) r.code = WEXITSTATUS(status);
  std::ifstream in(log);
  std::stringstream s;
  s << in.rdbuf();
  r.out = s.str();
  return r;
}

class PluginFault : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::path(plugslam::testing::buildDir()) / "tests" / "reliability_tmp" /
           ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    config_ = (dir_ / "run.yaml").string();
    std::ofstream(config_) << "plugins: [" << plugslam::testing::buildDir()
                           << "/tests/plugins/plugslam_fixture.so]\n"
                              "source: {type: fixture.CountingSource, frames: 20}\n"
                              "pipeline:\n  preprocessors:\n    - {type: fixture.Scale}\n"
                              "outputs: [fixture.SumWriter]\n";
  }
  Result run(const std::string& set1, const std::string& set2 = "") {
    std::vector<std::string> args{"run", config_, "-o", (dir_ / "out").string(), "--set", set1};
    if (!set2.empty()) args.insert(args.end(), {"--set", set2});
    return runCli(args, dir_ / "log.txt");
  }
  void expectReported(const Result& r, const std::string& module, const std::string& type) {
    EXPECT_FALSE(r.signalled) << r.out;
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("module '" + module + "' (" + type + ") failed"), std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("terminate called"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("Sanitizer"), std::string::npos) << r.out;
  }
  fs::path dir_;
  std::string config_;
};

TEST_F(PluginFault, PreprocessorThrowingIsReportedWithItsName) {
  const Result r = run("pipeline.preprocessors[0].fail_at=4");
  expectReported(r, "pipeline.preprocessors[0]", "fixture.Scale");
  EXPECT_NE(r.out.find("fixture Scale failure at frame 4"), std::string::npos) << r.out;
}

TEST_F(PluginFault, NonStandardExceptionFromAPreprocessorIsCaught) {
  const Result r =
      run("pipeline.preprocessors[0].fail_at=2", "pipeline.preprocessors[0].fail_with_int=true");
  expectReported(r, "pipeline.preprocessors[0]", "fixture.Scale");
  EXPECT_NE(r.out.find("not derived from std::exception"), std::string::npos) << r.out;
}

TEST_F(PluginFault, NonStandardExceptionFromASourceIsCaught) {
  const Result r = run("source.fail_at=3", "source.fail_with_int=true");
  expectReported(r, "source", "fixture.CountingSource");
}

TEST_F(PluginFault, SinkThrowingIsReportedWithItsName) {
  const Result r = run("outputs[0].fail_at=5");
  expectReported(r, "outputs[0]", "fixture.SumWriter");
  EXPECT_NE(r.out.find("fixture SumWriter failure at frame 5"), std::string::npos) << r.out;
}

TEST_F(PluginFault, StopPolicyWritesTheOutputsAndSavesTheSession) {
  const Result r = run("pipeline.preprocessors[0].fail_at=4");  // on_module_error: stop (default)
  expectReported(r, "pipeline.preprocessors[0]", "fixture.Scale");
  // The four frames before the failure reached the sink, whose end() still ran.
  EXPECT_EQ(readFile(dir_ / "out" / "sum.txt"), "4 12\n");
  const std::string json = readFile(dir_ / "out" / "run.json");
  EXPECT_NE(json.find("\"stopped_by\": \"error\""), std::string::npos) << json;
  EXPECT_NE(json.find("\"frames\": 4,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"error\": \"module 'pipeline.preprocessors[0]' (fixture.Scale) failed"),
            std::string::npos)
      << json;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "session" / "session.yaml")) << r.out;
  EXPECT_NE(r.out.find("session saved in"), std::string::npos) << r.out;
}

TEST_F(PluginFault, SinkFailingAtTheEndLeavesTheOtherOutputsAndTheSession) {
  std::ofstream(config_) << "plugins: [" << plugslam::testing::buildDir()
                         << "/tests/plugins/plugslam_fixture.so]\n"
                            "source: {type: fixture.CountingSource, frames: 20}\n"
                            "pipeline:\n  preprocessors:\n    - {type: fixture.Scale}\n"
                            "outputs:\n  - {type: fixture.SumWriter, fail_in_end: true}\n"
                            "  - {type: fixture.SumWriter, file: second.txt}\n";
  const Result r = run("max_frames=20");
  expectReported(r, "outputs[0]", "fixture.SumWriter");
  EXPECT_FALSE(fs::exists(dir_ / "out" / "sum.txt"));
  EXPECT_EQ(readFile(dir_ / "out" / "second.txt"), "20 380\n");
  const std::string json = readFile(dir_ / "out" / "run.json");
  EXPECT_NE(json.find("\"error\": \"module 'outputs[0]' (fixture.SumWriter) failed: fixture "
                      "SumWriter failure in end()\""),
            std::string::npos)
      << json;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "session" / "session.yaml")) << r.out;
}

TEST_F(PluginFault, SkipPolicySkipsTheFailingFrameAndGoesOn) {
  const Result r = run("pipeline.preprocessors[0].fail_at=4", "on_module_error=skip");
  EXPECT_FALSE(r.signalled) << r.out;
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("frame 4 skipped (on_module_error: skip): module "
                       "'pipeline.preprocessors[0]' (fixture.Scale) failed"),
            std::string::npos)
      << r.out;
  // 20 frames but the fourth: 2 * (0 + 1 + ... + 19 - 4).
  EXPECT_EQ(readFile(dir_ / "out" / "sum.txt"), "19 372\n");
  const std::string json = readFile(dir_ / "out" / "run.json");
  EXPECT_NE(json.find("\"module_errors\": 1,"), std::string::npos) << json;
  EXPECT_NE(json.find("\"stopped_by\": \"end of data\""), std::string::npos) << json;
}

TEST_F(PluginFault, SkipPolicyCountsEveryFailingSinkCall) {
  // The sink fails from its sixth frame on (its counter stops there): 15 frames skipped by it.
  const Result r = run("outputs[0].fail_at=5", "on_module_error=skip");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(readFile(dir_ / "out" / "sum.txt"), "5 20\n");
  EXPECT_NE(readFile(dir_ / "out" / "run.json").find("\"module_errors\": 15,"), std::string::npos);
  EXPECT_NE(r.out.find("15 frame(s) skipped because a module failed"), std::string::npos) << r.out;
}

TEST_F(PluginFault, SourceFailureStopsEvenUnderSkip) {
  const Result r = run("source.fail_at=3", "on_module_error=skip");
  expectReported(r, "source", "fixture.CountingSource");
  EXPECT_EQ(readFile(dir_ / "out" / "sum.txt"), "3 6\n");
}

// A real mapping run stopped by a failing module leaves a session that a new run continues.
TEST_F(PluginFault, SessionSavedOnStopIsContinued) {
  const std::string log =
      plugslam::testing::dataDir() + "/laser2d/intel-gfs-corrected/intel-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "no intel log at " << log << " (set PLUGSLAM_DATA)";
  std::string yaml = readFile(fs::path(plugslam::testing::sourceDir()) / "configs" /
                              "laser2d_carmen.yaml");
  const std::string plugins = "plugins: [io, laser2d, odometry]";
  const std::string preprocessors = "  preprocessors:\n";
  ASSERT_NE(yaml.find(plugins), std::string::npos);
  ASSERT_NE(yaml.find(preprocessors), std::string::npos);
  yaml.replace(yaml.find(plugins), plugins.size(),
               "plugins: [io, laser2d, odometry, " + plugslam::testing::buildDir() +
                   "/tests/plugins/plugslam_fixture.so]");
  yaml.insert(yaml.find(preprocessors) + preprocessors.size(),
              "    - {type: fixture.Scale, fail_at: 300}\n");
  std::ofstream(config_) << yaml;
  const Result first = run("source.path=" + log);
  expectReported(first, "pipeline.preprocessors[0]", "fixture.Scale");
  const fs::path session = dir_ / "out" / "session";
  ASSERT_TRUE(fs::exists(session / "session.yaml")) << first.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "trajectory.tum"));
  EXPECT_TRUE(fs::exists(dir_ / "out" / "map.pgm"));

  const Result second = runCli({"run", "--session", session.string(), "-o",
                                (dir_ / "out2").string(), "--set", "max_frames=50", "--set",
                                "pipeline.preprocessors[0].fail_at=-1"},
                               dir_ / "log2.txt");
  EXPECT_EQ(second.code, 0) << second.out;
  EXPECT_TRUE(std::regex_search(second.out, std::regex(": [1-9][0-9]* local maps, [1-9][0-9]* "
                                                       "edges \\(mapping\\)")))
      << second.out;
}

// Bad input met mid-run (a malformed line deep in a CARMEN log, strict policy) is still exit 2
// with the file and line, after the maps built so far were written and saved.
TEST_F(PluginFault, BadInputMidRunStillSavesWhatWasBuilt) {
  const std::string log =
      plugslam::testing::dataDir() + "/laser2d/intel-gfs-corrected/intel-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "no intel log at " << log << " (set PLUGSLAM_DATA)";
  // The first 3000 lines of the log, then a laser line whose readings are cut short.
  const fs::path cut = dir_ / "cut.log";
  const std::string command = "gzip -dc '" + log + "' | head -n 3000 > '" + cut.string() + "'";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ofstream(cut, std::ios::app) << "FLASER 180 1.0 2.0 3.0\n";
  const Result r = runCli({"run", plugslam::testing::sourceDir() + "/configs/laser2d_carmen.yaml",
                           "-o", (dir_ / "out").string(), "--set", "source.path=" + cut.string()},
                          dir_ / "log.txt");
  EXPECT_FALSE(r.signalled) << r.out;
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("cut.log:3001: FLASER"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "session" / "session.yaml")) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "trajectory.tum"));
  EXPECT_NE(readFile(dir_ / "out" / "run.json").find("\"stopped_by\": \"error\""),
            std::string::npos);
}

}  // namespace
