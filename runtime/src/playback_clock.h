#pragma once
// Paces a run at a playback rate by its frames' stamps (`plugslam run --rate R`).
#include <chrono>

namespace plugslam::runtime {

/// The help of the run's and the shell's --rate option.
inline constexpr const char* kPlaybackRateHelp =
    "playback rate: 0 = as fast as possible; R > 0 = paced by the frames' timestamps at R times "
    "the data's own speed (1 = as recorded, e.g. to watch a log with --serve; 2 = twice as fast)";

/// When each frame of a run is due at `rate` times the data's own speed: frame k is due at
/// anchor_wall + (stamp_k - anchor_stamp) / rate. Rate 0 = every frame due at once.
class PlaybackClock {
 public:
  using Clock = std::chrono::steady_clock;
  /// A lag beyond this restarts the clock at the late frame instead of rushing through the
  /// backlog: a pause, a pipeline slower than the data, or stamps that jump back. A shorter
  /// hiccup (a loop closure's optimization) is caught up, so the playback keeps the data's pace.
  static constexpr double kMaxLagSeconds = 0.5;

  /// A clock at `rate` (>= 0; 0 = as fast as possible).
  explicit PlaybackClock(double rate = 0);
  /// Changes the rate; the next frame restarts the clock.
  void setRate(double rate);
  /// The rate (0 = unpaced).
  double rate() const { return rate_; }
  /// When the frame stamped `stamp` (seconds) is due, the time being `now`: never before `now`
  /// for the first frame, a restart, a stamp that is not finite, or rate 0.
  Clock::time_point due(double stamp, Clock::time_point now);

 private:
  double rate_ = 0;
  bool anchored_ = false;
  Clock::time_point anchor_wall_{};
  double anchor_stamp_ = 0;
};

}  // namespace plugslam::runtime
