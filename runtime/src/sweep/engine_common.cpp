#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <boost/filesystem.hpp>
#include <cstdlib>
#include <sstream>

#include "plugslam/errors.h"
#include "sweep/engines.h"

namespace plugslam::runtime::sweep {

std::vector<const Case*> pendingCases(const Plan& plan, const std::string& dir) {
  std::vector<const Case*> out;
  for (const auto& c : plan.cases)
    if (!hasResult(dir, c.id)) out.push_back(&c);
  return out;
}

std::atomic<bool>& interruptFlag() {
  static std::atomic<bool> flag{false};
  return flag;
}

namespace {
extern "C" void onSweepSignal(int) { interruptFlag().store(true); }
}  // namespace

struct InterruptScope::Saved {
  struct sigaction interrupt {}, terminate {};
};

InterruptScope::InterruptScope() : saved_(new Saved) {
  interruptFlag() = false;
  struct sigaction sa {};
  sa.sa_handler = onSweepSignal;
  sigemptyset(&sa.sa_mask);
  // SIGTERM too: it is what scancel and a batch system's time limit send.
  ::sigaction(SIGINT, &sa, &saved_->interrupt);
  ::sigaction(SIGTERM, &sa, &saved_->terminate);
}

InterruptScope::~InterruptScope() {
  ::sigaction(SIGINT, &saved_->interrupt, nullptr);
  ::sigaction(SIGTERM, &saved_->terminate, nullptr);
  delete saved_;
}

FolderLock::FolderLock(const std::string& dir) {
  const std::string path = dir + "/.sweep.lock";
  fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError("cannot open '" + path + "'");
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError("another `plugslam sweep run` is running cases in '" + dir +
                     "': wait for it, or stop it (its finished cases are kept)");
  }
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

std::string findOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  if (!path) return "";
  std::stringstream dirs(path);
  for (std::string d; std::getline(dirs, d, ':');) {
    const std::string candidate = (d.empty() ? "." : d) + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return "";
}

}  // namespace plugslam::runtime::sweep
