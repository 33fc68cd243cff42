#include "sweep/process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>

namespace plugslam::runtime::sweep {

ProcessResult runProcess(const std::vector<std::string>& argv, const std::string& cwd,
                         const std::string& log, double timeout_s,
                         const std::function<bool()>& stop) {
  ProcessResult r;
  // Everything the child touches is made before fork: between fork and exec only
  // async-signal-safe calls are allowed (the parent has other threads).
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int out =
      log.empty() ? -1 : ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (!log.empty() && out < 0) {
    r.error = "cannot open '" + log + "': " + std::strerror(errno);
    return r;
  }
  // exec's failure comes back through a pipe that a successful exec closes: a program's own
  // exit 127 is its result, a binary that could not be started (being relinked, gone) is none.
  int exec_pipe[2];
  if (::pipe2(exec_pipe, O_CLOEXEC) != 0) {
    if (out >= 0) ::close(out);
    r.error = std::string("pipe failed: ") + std::strerror(errno);
    return r;
  }
  const pid_t parent = ::getpid();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    // A sweep killed outright takes its runs with it: no orphan writes into a case that the
    // next sweep runs again.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(127);
    const int in = ::open("/dev/null", O_RDONLY);
    if (in >= 0) ::dup2(in, 0);
    if (out >= 0) {
      ::dup2(out, 1);
      ::dup2(out, 2);
    }
    int failure = 0;
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) {
      failure = errno;
    } else {
      ::execv(args[0], args.data());
      failure = errno;
    }
    ssize_t ignored = ::write(exec_pipe[1], &failure, sizeof failure);
    (void)ignored;
    ::_exit(127);
  }
  if (out >= 0) ::close(out);
  ::close(exec_pipe[1]);
  if (pid < 0) {
    ::close(exec_pipe[0]);
    r.error = std::string("fork failed: ") + std::strerror(errno);
    return r;
  }
  int failure = 0;
  ssize_t got;
  do {
    got = ::read(exec_pipe[0], &failure, sizeof failure);
  } while (got < 0 && errno == EINTR);
  ::close(exec_pipe[0]);
  if (got == static_cast<ssize_t>(sizeof failure)) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    r.error = "could not run '" + argv[0] + "'" + (cwd.empty() ? "" : " in '" + cwd + "'") + ": " +
              std::strerror(failure);
    return r;
  }
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  int status = 0;
  struct rusage usage {};
  double term_at = -1;
  for (;;) {
    const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) break;
    const double t = elapsed();
    if (!r.interrupted && stop && stop()) {
      r.interrupted = true;
      ::kill(-pid, SIGINT);
      term_at = t + 10;  // a run saves its session on SIGINT; it gets that long
    }
    if (!r.timed_out && !r.interrupted && timeout_s > 0 && t > timeout_s) {
      r.timed_out = true;
      ::kill(-pid, SIGTERM);
      term_at = t + 5;
    }
    if (term_at >= 0 && t > term_at) {
      ::kill(-pid, SIGKILL);
      term_at = -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(t < 1 ? 5 : 25));
  }
  r.wall_s = elapsed();
  r.peak_rss_mib = usage.ru_maxrss / 1024.0;  // KiB on Linux
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  return r;
}

std::vector<std::string> tailLines(const std::string& path, size_t lines) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff from = size > 4096 ? size - 4096 : 0;
  in.seekg(from);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::string> all;
  size_t at = 0;
  // A cut first line is dropped when the read started mid-file.
  if (from > 0) at = text.find('\n') == std::string::npos ? text.size() : text.find('\n') + 1;
  while (at < text.size()) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(at, end - at);
    // Progress lines redraw with \r: keep what the last draw showed.
    if (auto cr = line.find_last_of('\r'); cr != std::string::npos) line = line.substr(cr + 1);
    all.push_back(line);
    at = end + 1;
  }
  while (!all.empty() && all.back().empty()) all.pop_back();
  if (all.size() > lines) all.erase(all.begin(), all.end() - static_cast<long>(lines));
  return all;
}

}  // namespace plugslam::runtime::sweep
