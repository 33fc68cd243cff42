#include "view/job_thread.h"

#include <spdlog/spdlog.h>

#include <exception>
#include <utility>

namespace plugslam::runtime {

JobThread::JobThread(std::size_t max_pending, std::string failure, OnStop on_stop)
    : max_pending_(max_pending), failure_(std::move(failure)), on_stop_(on_stop) {
  thread_ = std::thread([this] { loop(); });
}

JobThread::~JobThread() { stop(); }

JobThread::Posted JobThread::post(std::function<void()> job) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return Posted::kStopped;
    if (jobs_.size() >= max_pending_) return Posted::kFull;
    jobs_.push_back(std::move(job));
  }
  cv_.notify_one();
  return Posted::kQueued;
}

void JobThread::stop() {
  std::deque<std::function<void()>> dropped;  // destroyed outside the lock
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stop_) return;
    stop_ = true;
    if (on_stop_ == OnStop::kDropWaiting) dropped.swap(jobs_);
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void JobThread::loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    cv_.wait(lock, [&] { return stop_ || !jobs_.empty(); });
    if (jobs_.empty()) return;  // stopping, nothing left to run
    auto job = std::move(jobs_.front());
    jobs_.pop_front();
    lock.unlock();
    try {
      job();
    } catch (const std::exception& e) {
      spdlog::warn("{}: {}", failure_, e.what());
    }
    lock.lock();
  }
}

}  // namespace plugslam::runtime
