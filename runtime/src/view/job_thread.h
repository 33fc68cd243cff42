#pragma once
// A thread of its own for viewer requests that must wait neither on the server's thread nor on
// the run's (a shell command, a config rebuilt to validate a setting): jobs run one at a time in
// the order they came, and a bounded queue keeps a client that sends too many from piling work up.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace plugslam::runtime {

/// Runs queued jobs in order on one thread; a job's exception is logged, not passed on.
class JobThread {
 public:
  /// What post() did with a job.
  enum class Posted { kQueued, kFull, kStopped };
  /// What stop() does with the jobs still waiting.
  enum class OnStop { kRunWaiting, kDropWaiting };

  /// Starts the thread. `max_pending` bounds the queue; `failure` begins the warning logged when
  /// a job throws.
  JobThread(std::size_t max_pending, std::string failure, OnStop on_stop);
  ~JobThread();
  JobThread(const JobThread&) = delete;
  JobThread& operator=(const JobThread&) = delete;

  /// Queues `job` unless the thread is stopped or `max_pending` jobs wait already.
  Posted post(std::function<void()> job);
  /// Ends the thread after the job it runs (and the waiting ones with kRunWaiting); later posts
  /// are refused. Idempotent.
  void stop();

 private:
  void loop();

  const std::size_t max_pending_;
  const std::string failure_;
  const OnStop on_stop_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> jobs_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace plugslam::runtime
