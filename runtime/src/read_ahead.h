#pragma once
// Reads a run's frames ahead of the pipeline on a thread of their own: a source decodes images
// (PNG, JPEG, compressed bag messages) while the pipeline tracks the previous frame, so what a
// user waits for approaches the pipeline's own rate. Frames come out in the order read, at most
// `depth` wait; whatever the reader throws comes out, unchanged, where its frame would have.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "plugslam/frame.h"

namespace plugslam::runtime {

/// One frame read ahead, or the end of the data, or what reading threw.
struct ReadFrame {
  std::unique_ptr<Frame> frame;  ///< nullptr at the end of the data (or on error)
  std::exception_ptr error;      ///< what reading this frame threw
  double seconds = 0;            ///< time the read took
};

/// A bounded queue filled by one reader thread.
class ReadAhead {
 public:
  /// `read(frame)` fills a fresh frame whose seq is set; false at the end of the data. It runs on
  /// the reader thread only, one frame at a time.
  using Reader = std::function<bool(Frame&)>;
  /// Called on the reader thread each time it waits for room, `depth` frames queued: the event
  /// by which a test sees the bound hold without waiting for a reader that might overshoot.
  using FullHook = std::function<void()>;
  /// Starts reading: at most `depth` (>= 1) frames wait.
  ReadAhead(Reader read, size_t depth, FullHook on_full = {});
  /// Stops the reader (after the read in progress) and joins it.
  ~ReadAhead();
  ReadAhead(const ReadAhead&) = delete;
  ReadAhead& operator=(const ReadAhead&) = delete;

  /// The next frame in order, waiting for it; after the end or an error, the same again.
  ReadFrame next();

 private:
  void run();
  Reader read_;
  size_t depth_;
  FullHook on_full_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<ReadFrame> queue_;
  bool stop_ = false;
  uint64_t seq_ = 0;
  std::thread thread_;
};

}  // namespace plugslam::runtime
