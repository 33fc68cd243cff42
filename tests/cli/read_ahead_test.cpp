// Frames read ahead of the pipeline on their own thread: in order, bounded, errors where their
// frame would have been, and a reader stopped early does not hang.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <stdexcept>

#include "read_ahead.h"

using plugslam::Frame;
using plugslam::runtime::ReadAhead;
using plugslam::runtime::ReadFrame;

TEST(ReadAhead, FramesComeInOrderThenTheEnd) {
  int calls = 0;
  ReadAhead reader(
      [&calls](Frame& f) {
        if (calls == 100) return false;
        f.stamp = 0.1 * calls++;
        return true;
      },
      3);
  for (int k = 0; k < 100; ++k) {
    ReadFrame r = reader.next();
    ASSERT_TRUE(r.frame) << k;
    EXPECT_FALSE(r.error);
    EXPECT_EQ(r.frame->seq, static_cast<uint64_t>(k));
    EXPECT_DOUBLE_EQ(r.frame->stamp, 0.1 * k);
  }
  for (int again = 0; again < 2; ++again) {
    const ReadFrame end = reader.next();
    EXPECT_FALSE(end.frame);
    EXPECT_FALSE(end.error);
  }
}

TEST(ReadAhead, AtMostDepthFramesWait) {
  std::atomic<int> reads{0};
  std::mutex mutex;
  std::condition_variable changed;
  int fulls = 0;  // times the reader waited for room
  ReadAhead reader(
      [&reads](Frame&) {
        ++reads;
        return true;
      },
      4,
      [&] {
        {
          std::lock_guard<std::mutex> lock(mutex);
          ++fulls;
        }
        changed.notify_all();
      });
  const auto waitForFull = [&](int n) {
    std::unique_lock<std::mutex> lock(mutex);
    changed.wait(lock, [&] { return fulls >= n; });
  };
  // Nobody takes a frame: the reader fills the queue and waits, reading nothing more.
  waitForFull(1);
  EXPECT_EQ(reads.load(), 4);
  // One frame taken: one more read fills the queue again.
  reader.next();
  waitForFull(2);
  EXPECT_EQ(reads.load(), 5);
}

TEST(ReadAhead, AnErrorComesWhereItsFrameWouldHave) {
  int calls = 0;
  ReadAhead reader(
      [&calls](Frame&) {
        if (calls++ == 2) throw std::runtime_error("log.clf:3: expected a number");
        return true;
      },
      8);
  EXPECT_TRUE(reader.next().frame);
  EXPECT_TRUE(reader.next().frame);
  for (int again = 0; again < 2; ++again) {
    const ReadFrame r = reader.next();
    EXPECT_FALSE(r.frame);
    ASSERT_TRUE(r.error);
    try {
      std::rethrow_exception(r.error);
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "log.clf:3: expected a number");
    }
  }
  EXPECT_EQ(calls, 3) << "nothing is read after the error";
}

TEST(ReadAhead, StoppingEarlyJoinsTheReader) {
  // An endless source, abandoned after two frames (max_frames, Ctrl-C): the destructor returns
  // (a reader left running would hang the test) and no read happens after it.
  std::atomic<int> reads{0}, reads_after{0};
  std::atomic<bool> gone{false};
  {
    ReadAhead reader(
        [&](Frame&) {
          ++reads;
          if (gone) ++reads_after;
          return true;
        },
        2);
    reader.next();
    reader.next();
  }
  gone = true;
  EXPECT_EQ(reads_after.load(), 0);
  EXPECT_LE(reads.load(), 2 + 2 + 1);
}
