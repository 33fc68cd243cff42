#include "sources/replay.h"

#include <spdlog/spdlog.h>

#include <utility>

namespace plugslam {
namespace io {

void Replay::restart(std::string log) {
  log_ = std::move(log);
  pass_ = 1;
  period_ = 0;
  offset_ = 0;
  offset_due_ = false;
  anchor_.reset();
  frames_ = 0;
  first_ = last_ = 0;
}

double Replay::shift(double log_stamp) {
  if (offset_due_) {
    // At the first stamp of the pass rather than at its start: frames the source gave in between
    // without a stamp of the log's own (synthesised ones) still come before it.
    offset_ = last_ + period_ - anchor_.value_or(log_stamp);
    offset_due_ = false;
  }
  return log_stamp + offset_;
}

void Replay::frame(double stamp) {
  if (frames_++ == 0) first_ = stamp;
  last_ = stamp;
}

bool Replay::next(int64_t repeat, double fallback_period) {
  if (repeat != 0 && pass_ >= repeat) return false;
  period_ = frames_ > 1 ? (last_ - first_) / static_cast<double>(frames_ - 1) : fallback_period;
  if (!(period_ > 0)) period_ = fallback_period;
  frames_ = 0;
  offset_due_ = true;
  ++pass_;
  spdlog::info("{}: replay {}{} from t = {:.3f} s", log_, pass_,
               repeat > 0 ? " of " + std::to_string(repeat) : std::string(" (endless)"),
               last_ + period_);
  return true;
}

}  // namespace io
}  // namespace plugslam
