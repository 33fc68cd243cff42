// Faults in plugin modules during a run: whatever a source, preprocessor or sink throws (a
// std::exception or anything else) is caught at the module boundary and reported with the
// module's path and type (plugin.Type); the process exits 1 without crashing.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_paths.h"

namespace fs = std::filesystem;

namespace {

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

}  // namespace
