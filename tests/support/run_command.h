#pragma once
// A shell command as a user runs it, for the tests that drive the CLI: its exit code and
// everything it printed, and expectations on that. Header-only.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <initializer_list>
#include <string>

namespace plugslam::testing {

/// The exit code of a command (-1 when it did not exit normally) and its stdout and stderr.
struct CommandResult {
  int code = -1;
  std::string out;
};

/// Runs `cmd` through /bin/sh with stderr joined to stdout, and waits for it.
inline CommandResult runCommand(const std::string& cmd) {
  CommandResult r;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// Expects `part` in what a command printed, showing all of it when it is missing.
inline void expectHas(const std::string& out, const std::string& part) {
  EXPECT_NE(out.find(part), std::string::npos) << "'" << part << "' not in:\n" << out;
}

/// Expects each of `parts` in what a command printed.
inline void expectHasAll(const std::string& out, std::initializer_list<std::string> parts) {
  for (const auto& part : parts) expectHas(out, part);
}

/// Expects a command to have exited with `code` and printed each of `parts`.
inline void expectExit(const CommandResult& r, int code, std::initializer_list<std::string> parts) {
  EXPECT_EQ(r.code, code) << r.out;
  expectHasAll(r.out, parts);
}

}  // namespace plugslam::testing
