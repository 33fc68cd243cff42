// Runs every case of tests/bad_input/cases.yaml through the real binaries (build/bin/plugslam or
// bad_input_tool) and checks the exit code, the message pattern, and that nothing crashed: no
// signal, no sanitizer report, no std::terminate.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "test_paths.h"

namespace fs = std::filesystem;

namespace {

struct Case {
  std::string name;
  std::string file;     // relative to tests/bad_input
  std::string command;  // arguments with {file}, {dir}, {tmp}
  int exit_code = 2;
  std::string pattern;
  std::string binary = "plugslam";
  std::string why;
  bool missing = false;  // the case is about a file that does not exist
};

// Shown by GoogleTest instead of the raw bytes of a parameter.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::string corpusDir() { return plugslam::testing::sourceDir() + "/tests/bad_input"; }

std::vector<Case> loadCases() {
  std::vector<Case> cases;
  try {
    YAML::Node root = YAML::LoadFile(corpusDir() + "/cases.yaml");
    for (const auto& n : root["cases"]) {
      Case c;
      c.name = n["name"].as<std::string>();
      c.file = n["file"].as<std::string>();
      c.command = n["command"].as<std::string>();
      c.exit_code = n["exit"].as<int>();
      c.pattern = n["pattern"].as<std::string>();
      if (n["binary"]) c.binary = n["binary"].as<std::string>();
      if (n["why"]) c.why = n["why"].as<std::string>();
      if (n["missing"]) c.missing = n["missing"].as<bool>();
      cases.push_back(c);
    }
  } catch (const std::exception&) {
    // ManifestIsComplete reports the problem; no parameterised case is instantiated.
    cases.clear();
  }
  return cases;
}

void replaceAll(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t pos = s.find(from); pos != std::string::npos;
       pos = s.find(from, pos + to.size()))
    s.replace(pos, from.size(), to);
}

struct Outcome {
  bool signalled = false;
  bool timed_out = false;
  int signal = 0;
  int exit_code = -1;
  std::string output;
};

// fork/exec with stdout and stderr both into `log`; the child is killed by SIGALRM after
// `timeout` (an alarm survives exec), so the parent just waits for it to end.
Outcome runProcess(const std::vector<std::string>& args, const std::string& log,
                   std::chrono::seconds timeout) {
  Outcome out;
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) _exit(127);
    dup2(fd, 1);
    dup2(fd, 2);
    close(fd);
    alarm(static_cast<unsigned>(timeout.count()));
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  out.timed_out = WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM;
  if (WIFSIGNALED(status)) {
    out.signalled = true;
    out.signal = WTERMSIG(status);
  } else if (WIFEXITED(status)) {
    out.exit_code = WEXITSTATUS(status);
  }
  std::ifstream in(log, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  out.output = text.str();
  return out;
}

std::vector<std::string> splitArgs(const std::string& command) {
  std::istringstream in(command);
  std::vector<std::string> args;
  for (std::string a; in >> a;) args.push_back(a);
  return args;
}

class BadInput : public ::testing::TestWithParam<Case> {};

TEST_P(BadInput, ExitCodeAndMessage) {
  const Case& c = GetParam();
  const std::string build = plugslam::testing::buildDir();
  const std::string exe =
      c.binary == "tool" ? build + "/tests/bad_input_tool" : build + "/bin/plugslam";
  ASSERT_TRUE(fs::exists(exe)) << exe << " is not built";
  const fs::path tmp = fs::path(build) / "tests" / "bad_input_tmp" / c.name;
  fs::remove_all(tmp);
  fs::create_directories(tmp);

  std::string command = c.command;
  replaceAll(command, "{file}", corpusDir() + "/" + c.file);
  replaceAll(command, "{dir}", corpusDir());
  replaceAll(command, "{tmp}", tmp.string());
  std::vector<std::string> args{exe};
  for (auto& a : splitArgs(command)) args.push_back(a);

  const Outcome out = runProcess(args, (tmp / "output.txt").string(), std::chrono::seconds(60));
  const std::string shown =
      "case " + c.name + " (" + c.why + ")\ncommand: " + command + "\noutput:\n" + out.output;
  ASSERT_FALSE(out.timed_out) << "timed out; " << shown;
  ASSERT_FALSE(out.signalled) << "killed by signal " << out.signal << "; " << shown;
  for (const char* crash : {"AddressSanitizer", "LeakSanitizer",
                            "runtime error:", "terminate called", "Segmentation fault"}) {
    EXPECT_EQ(out.output.find(crash), std::string::npos)
        << "crash report '" << crash << "'; " << shown;
  }
  EXPECT_EQ(out.exit_code, c.exit_code) << shown;
  std::string pattern = c.pattern;
  auto flags = std::regex::ECMAScript;
  if (pattern.rfind("(?i)", 0) == 0) {
    pattern = pattern.substr(4);
    flags |= std::regex::icase;
  }
  EXPECT_TRUE(std::regex_search(out.output, std::regex(pattern, flags)))
      << "pattern /" << c.pattern << "/ not found; " << shown;
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) { return info.param.name; }

INSTANTIATE_TEST_SUITE_P(Corpus, BadInput, ::testing::ValuesIn(loadCases()), caseName);

TEST(BadInputCorpus, ManifestIsComplete) {
  const auto cases = loadCases();
  ASSERT_GE(cases.size(), 60u) << "cases.yaml missing, malformed or too small";
  for (const auto& c : cases) {
    const fs::path file = fs::path(corpusDir()) / c.file;
    if (c.missing) {
      EXPECT_FALSE(fs::exists(file)) << c.name << ": the missing file exists";
    } else {
      ASSERT_TRUE(fs::exists(file)) << c.name << ": " << file;
      // A case is one file, or a folder holding a small dataset (the camera layouts).
      std::uintmax_t size = 0;
      if (fs::is_directory(file)) {
        for (const auto& e : fs::recursive_directory_iterator(file))
          if (e.is_regular_file()) size += e.file_size();
      } else {
        size = fs::file_size(file);
      }
      EXPECT_LT(size, 20u * 1024u) << c.name << " is not small";
    }
    EXPECT_TRUE(c.exit_code == 0 || c.exit_code == 2) << c.name;
    EXPECT_FALSE(c.pattern.empty()) << c.name;
  }
}

}  // namespace
