#include "read_ahead.h"

#include <chrono>
#include <utility>

namespace plugslam::runtime {

ReadAhead::ReadAhead(Reader read, size_t depth, FullHook on_full)
    : read_(std::move(read)),
      depth_(depth > 0 ? depth : 1),
      on_full_(std::move(on_full)),
      thread_([this] { run(); }) {}

ReadAhead::~ReadAhead() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void ReadAhead::run() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (on_full_ && !stop_ && queue_.size() >= depth_) {
        lock.unlock();  // so the hook may lock what a caller of next() holds
        on_full_();
        lock.lock();
      }
      changed_.wait(lock, [this] { return stop_ || queue_.size() < depth_; });
      if (stop_) return;
    }
    ReadFrame item;
    auto frame = std::make_unique<Frame>();
    frame->seq = seq_;
    const auto start = std::chrono::steady_clock::now();
    bool more = false;
    try {
      more = read_(*frame);
    } catch (...) {
      item.error = std::current_exception();
    }
    item.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const bool last = !more || item.error;
    if (!last) {
      frame->seq = seq_++;
      item.frame = std::move(frame);
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(std::move(item));
    }
    changed_.notify_all();
    if (last) return;
  }
}

ReadFrame ReadAhead::next() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return !queue_.empty(); });
  ReadFrame item = std::move(queue_.front());
  if (item.frame) {
    queue_.pop_front();
    changed_.notify_all();
  } else {
    // The end, or an error: it stays at the front, for every later call alike.
    queue_.front().error = item.error;
    queue_.front().seconds = 0;
  }
  return item;
}

}  // namespace plugslam::runtime
