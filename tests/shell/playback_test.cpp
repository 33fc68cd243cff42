// Paced playback (`plugslam run --rate R`): the clock's schedule on made-up times (due times,
// catch-up of a short hiccup, a restart after a long lag or a stamp going back), then real runs
// of the lmsim pipeline (10 Hz stamps): a paced run waits for each frame at its stamp / R (the
// waits recorded, not timed), frames stepped by hand are due on the schedule, and Ctrl-C ends a
// long wait.
#include "playback_clock.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/errors.h"
#include "run_config.h"
#include "runner.h"
#include "temp_dir.h"
#include "test_paths.h"

using namespace plugslam;
using namespace plugslam::runtime;
using Clock = PlaybackClock::Clock;

namespace {

Clock::time_point at(double seconds) {
  return Clock::time_point{} + std::chrono::duration_cast<Clock::duration>(
                                   std::chrono::duration<double>(seconds));
}
double seconds(Clock::time_point t) { return std::chrono::duration<double>(t - Clock::time_point{}).count(); }

// Times compare within 1 us: the steady clock ticks in ns, and doubles of ~10 s carry ~1e-15 s.
TEST(PlaybackClock, PacesByStampsAtTheRate) {
  PlaybackClock clock(2.0);  // twice the data's speed
  EXPECT_DOUBLE_EQ(seconds(clock.due(100.0, at(5))), 5.0);  // the first frame: at once
  EXPECT_NEAR(seconds(clock.due(100.1, at(5.01))), 5.05, 1e-6);
  EXPECT_NEAR(seconds(clock.due(101.0, at(5.06))), 5.5, 1e-6);
  // Late by 0.3 s (a loop closure's optimization): still due at its time, so it is caught up.
  EXPECT_NEAR(seconds(clock.due(102.0, at(6.3))), 6.0, 1e-6);
}

TEST(PlaybackClock, UnpacedAndUnstampedFramesAreDueAtOnce) {
  PlaybackClock clock(0.0);
  EXPECT_DOUBLE_EQ(seconds(clock.due(0.0, at(1))), 1.0);
  EXPECT_DOUBLE_EQ(seconds(clock.due(50.0, at(1.5))), 1.5);
  clock.setRate(1.0);
  EXPECT_DOUBLE_EQ(seconds(clock.due(NAN, at(2))), 2.0);
  EXPECT_THROW(clock.setRate(-1), InputError);
  EXPECT_THROW(clock.setRate(NAN), InputError);
}

TEST(PlaybackClock, RestartsAfterALongLagOrAStampGoingBack) {
  PlaybackClock clock(1.0);
  clock.due(0.0, at(0));
  EXPECT_NEAR(seconds(clock.due(1.0, at(0.2))), 1.0, 1e-6);
  // Paused for 10 s: the next frame is due now, and the ones after it at the data's pace from
  // there, not all at once to catch up.
  EXPECT_NEAR(seconds(clock.due(2.0, at(11.0))), 11.0, 1e-6);
  EXPECT_NEAR(seconds(clock.due(3.0, at(11.1))), 12.0, 1e-6);
  // A stamp going back (a log restarted): restarted there.
  EXPECT_NEAR(seconds(clock.due(0.5, at(11.2))), 11.2, 1e-6);
  EXPECT_NEAR(seconds(clock.due(1.5, at(11.3))), 12.2, 1e-6);
  // A new rate restarts the clock at the next frame.
  clock.setRate(4.0);
  EXPECT_NEAR(seconds(clock.due(2.5, at(11.4))), 11.4, 1e-6);
  EXPECT_NEAR(seconds(clock.due(4.5, at(11.5))), 11.9, 1e-6);
}

class Playback : public ::testing::Test {
 protected:
  void SetUp() override {
    plugins_.addSearchDir(plugslam::testing::buildDir() + "/tests/plugins");
  }
  // The lmsim pipeline (10 Hz stamps: frame k at 0.1 k s), `frames` frames.
  std::shared_ptr<RunConfig> build(int frames) {
    std::ifstream in(plugslam::testing::sourceDir() + "/tests/shell/lmsim.yaml");
    std::stringstream ss;
    ss << in.rdbuf();
    ConfigDocument doc = loadConfigText(ss.str(), "<lmsim>");
    applyOverride(doc, "max_frames=" + std::to_string(frames));
    return buildRun(doc, plugins_);
  }
  RunOptions options(double rate) {
    RunOptions o;
    o.out_dir = dir_.file("out");
    o.rate = rate;
    return o;
  }
  plugslam::testing::TempDir dir_{"plugslam_playback"};
  PluginManager plugins_;
};

TEST_F(Playback, APacedRunWaitsForEachFrameAtItsStampOverTheRate) {
  // 21 frames = 2.0 s of data; at rate 0.01 frame k is due 10 k s after the first. The run's
  // waits are recorded instead of slept, so the run takes no longer for it, and no machine is
  // slow enough to be 0.5 s late on a 10 s schedule (which would restart it).
  auto run = build(21);
  RunOptions o = options(0.01);
  std::vector<Clock::time_point> waits;
  o.wait_until = [&](Clock::time_point due) { waits.push_back(due); };
  const RunReport report = runPipeline(*run, o);
  EXPECT_EQ(report.frames, 21u);
  EXPECT_EQ(report.stopped_by, "max_frames");
  ASSERT_EQ(waits.size(), 22u);  // and once more for the end of the data (max_frames), at once
  for (size_t k = 1; k < 21; ++k)
    EXPECT_NEAR(std::chrono::duration<double>(waits[k] - waits[0]).count(), 10.0 * k, 1e-6)
        << "frame " << k;
}

TEST_F(Playback, FramesSteppedByHandAreDueOnTheSchedule) {
  auto run = build(6);
  Execution execution(*run, options(10.0));  // 0.1 s of data = 10 ms
  const auto first = execution.nextDue();
  EXPECT_EQ(execution.nextDue(), first) << "the frame is read once";
  ASSERT_TRUE(execution.step());
  auto anchor = first;  // where the schedule started (it restarts after a long lag)
  int anchor_k = 0;
  const auto lag = [](Clock::time_point now, Clock::time_point due) {
    return std::chrono::duration<double>(now - due).count();
  };
  // Each frame is stepped at once, not at its time: on time or a short lag keeps the schedule.
  for (int k = 1; k < 6; ++k) {
    const auto before = Clock::now();
    const auto due = execution.nextDue();
    const auto after = Clock::now();
    const auto scheduled = anchor + std::chrono::duration_cast<Clock::duration>(
                                        std::chrono::duration<double>(0.01 * (k - anchor_k)));
    // The clock read "now" between `before` and `after`: a lag longer than kMaxLagSeconds (this
    // test descheduled on a loaded machine) restarts the schedule at once.
    const bool on_schedule = std::abs(lag(due, scheduled)) < 1e-6;
    if (lag(after, scheduled) <= PlaybackClock::kMaxLagSeconds) {
      EXPECT_TRUE(on_schedule) << "frame " << k << " due " << lag(due, scheduled) << " s off";
    } else if (lag(before, scheduled) > PlaybackClock::kMaxLagSeconds) {
      EXPECT_TRUE(due >= before && due <= after) << "frame " << k << " not restarted at once";
    }
    if (!on_schedule) {
      anchor = due;
      anchor_k = k;
    }
    ASSERT_TRUE(execution.step());
  }
  EXPECT_FALSE(execution.step());
  EXPECT_EQ(execution.frames(), 6u);
  execution.finish();
}

TEST_F(Playback, CtrlCEndsALongWait) {
  // Rate 1e-6: the second frame is due 10^5 s (28 hours) after the first, so only the interrupt
  // can end this run. The runner asks before each frame and while it waits: the third question
  // is asked during the wait for the second frame.
  auto run = build(5);
  RunOptions o = options(1e-6);
  int asked = 0;
  o.interrupted = [&] { return ++asked >= 3; };
  bool saved = false;
  o.on_interrupt = [&] { saved = true; };
  const RunReport report = runPipeline(*run, o);
  EXPECT_EQ(report.stopped_by, "interrupted");
  EXPECT_TRUE(saved);
  EXPECT_EQ(report.frames, 1u);
  EXPECT_EQ(asked, 3);
}

}  // namespace
