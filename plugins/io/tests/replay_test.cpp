// The replay clock shared by the log sources' `repeat`: stamps keep increasing across passes,
// each pass spaced from the previous one by its mean frame period.
#include "sources/replay.h"

#include <gtest/gtest.h>

#include <initializer_list>

namespace plugslam::io {
namespace {

// Pass 1 of a log whose frames carry `stamps` (the first is the anchor), and the next pass begun.
void playFirstPass(Replay& replay, std::initializer_list<double> stamps, int64_t repeat) {
  replay.restart("test log");
  replay.anchor(*stamps.begin());
  for (double t : stamps) replay.frame(replay.shift(t));
  ASSERT_TRUE(replay.next(repeat, 0.1));
}

TEST(Replay, LaterPassesFollowThePreviousOneByItsFramePeriod) {
  Replay replay;
  replay.restart("test log");
  EXPECT_EQ(replay.pass(), 1);
  for (double t : {10.0, 10.5, 11.0}) {
    replay.anchor(t);
    EXPECT_EQ(replay.shift(t), t);  // pass 1 keeps the log's own clock
    replay.frame(t);
  }
  ASSERT_TRUE(replay.next(3, 0.1));
  EXPECT_EQ(replay.pass(), 2);
  // Mean period 0.5 s: the log's first frame (10.0) comes at 11.5; all stamps move alike.
  EXPECT_DOUBLE_EQ(replay.shift(10.0), 11.5);
  EXPECT_DOUBLE_EQ(replay.shift(10.25), 11.75);
  replay.anchor(10.0);  // only pass 1's anchor counts
  for (double t : {10.0, 10.5, 11.0}) replay.frame(replay.shift(t));
  ASSERT_TRUE(replay.next(3, 0.1));
  EXPECT_DOUBLE_EQ(replay.shift(10.0), 13.0);  // pass 2 ended at 12.5
  for (double t : {10.0, 10.5, 11.0}) replay.frame(replay.shift(t));
  EXPECT_FALSE(replay.next(3, 0.1));  // three passes played
  EXPECT_EQ(replay.pass(), 3);
}

TEST(Replay, APassOfOneFrameUsesTheFallbackPeriod) {
  Replay replay;
  replay.restart("test log");
  replay.anchor(5.0);
  replay.frame(replay.shift(5.0));
  ASSERT_TRUE(replay.next(0, 0.25));  // 0: endless
  EXPECT_DOUBLE_EQ(replay.shift(5.0), 5.25);
  // Frames at the same stamp have no positive period either.
  replay.frame(5.25);
  replay.frame(5.25);
  ASSERT_TRUE(replay.next(0, 0.25));
  EXPECT_DOUBLE_EQ(replay.shift(5.0), 5.5);
}

TEST(Replay, TheOffsetIsFixedAtThePassFirstStampAfterFramesWithoutOne) {
  Replay replay;
  playFirstPass(replay, {1.0, 2.0}, 2);
  // The source gave a frame with a synthesised stamp before the pass's first timed one: the
  // timed one still comes one period after it, not before.
  replay.frame(3.0);
  EXPECT_DOUBLE_EQ(replay.shift(1.0), 4.0);
  EXPECT_DOUBLE_EQ(replay.shift(2.0), 5.0);  // and the offset stays for the pass
}

TEST(Replay, RestartGoesBackToTheLogClock) {
  Replay replay;
  playFirstPass(replay, {1.0, 2.0}, 0);
  EXPECT_NE(replay.shift(1.0), 1.0);
  replay.restart("b");
  EXPECT_EQ(replay.pass(), 1);
  EXPECT_EQ(replay.shift(1.0), 1.0);
}

TEST(Replay, TotalFramesOfAllPasses) {
  EXPECT_EQ(Replay::total(100, 3), 300);
  EXPECT_EQ(Replay::total(100, 1), 100);
  EXPECT_EQ(Replay::total(100, 0), -1);  // endless
  EXPECT_EQ(Replay::total(-1, 3), -1);   // unknown length
}

}  // namespace
}  // namespace plugslam::io
