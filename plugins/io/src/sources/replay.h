#pragma once
// Replays of a recorded log, behind the `repeat` parameter of the log sources (CARMEN, ROS bag):
// the pass count and one clock across passes, so a soak test can run a log for hours.
#include <cstdint>
#include <optional>
#include <string>

namespace plugslam {
namespace io {

/// Plays a log `repeat` times (0: endlessly). Pass 1 keeps the log's stamps; each later pass is
/// shifted by one offset, so that its first frame comes one frame period (the previous pass's
/// mean, or a fallback) after the frame before it: stamps keep increasing and the streams of a
/// log keep their relative timing. The source reopens its own reader.
class Replay {
 public:
  /// Back to pass 1 with the log's own clock; `log` names the log in messages, e.g.
  /// "CARMEN log 'lab.log'".
  void restart(std::string log);
  /// The current pass, 1-based.
  int64_t pass() const { return pass_; }
  /// The log's own stamp of the first frame of pass 1: each later pass puts it one frame period
  /// after the frame before that pass's first shifted stamp. Later calls are ignored.
  void anchor(double log_stamp) {
    if (pass_ == 1 && !anchor_) anchor_ = log_stamp;
  }
  /// A stamp on the log's clock, moved onto the run's clock of this pass. A later pass fixes its
  /// offset at its first call, from the last frame given by then.
  double shift(double log_stamp);
  /// A frame was given `stamp` (on the run's clock).
  void frame(double stamp);
  /// At the end of a pass: false when it was the last of `repeat`; otherwise starts the next
  /// pass, spaced by the mean frame period of the one that ended (`fallback_period` when it had
  /// fewer than two frames or no positive period), and logs where it starts.
  bool next(int64_t repeat, double fallback_period);
  /// Frames of every pass from the frames of one (-1 when replaying endlessly or `once` < 0).
  static int64_t total(int64_t once, int64_t repeat) {
    return repeat == 0 || once < 0 ? -1 : once * repeat;
  }

 private:
  std::string log_ = "log";
  int64_t pass_ = 1;
  double period_ = 0;
  double offset_ = 0;
  bool offset_due_ = false;  // a later pass whose offset is not fixed yet
  std::optional<double> anchor_;
  // The frames of the current pass: how many, the first stamp; and the last frame's stamp.
  uint64_t frames_ = 0;
  double first_ = 0, last_ = 0;
};

}  // namespace io
}  // namespace plugslam
