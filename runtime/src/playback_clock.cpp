#include "playback_clock.h"

#include <cmath>

#include "plugslam/errors.h"

namespace plugslam::runtime {

PlaybackClock::PlaybackClock(double rate) { setRate(rate); }

void PlaybackClock::setRate(double rate) {
  if (!std::isfinite(rate) || rate < 0)
    throw InputError("playback rate must be a number >= 0 (0: as fast as possible, 1: the "
                     "data's own speed)");
  rate_ = rate;
  anchored_ = false;
}

PlaybackClock::Clock::time_point PlaybackClock::due(double stamp, Clock::time_point now) {
  if (rate_ <= 0 || !std::isfinite(stamp)) return now;
  if (anchored_) {
    const auto offset = std::chrono::duration<double>((stamp - anchor_stamp_) / rate_);
    const auto due = anchor_wall_ + std::chrono::round<Clock::duration>(offset);
    const double lag = std::chrono::duration<double>(now - due).count();
    if (stamp >= anchor_stamp_ && lag <= kMaxLagSeconds) return due;
  }
  anchored_ = true;
  anchor_wall_ = now;
  anchor_stamp_ = stamp;
  return now;
}

}  // namespace plugslam::runtime
