#pragma once
// The status line: one line of progress at the bottom of a terminal that log lines never land
// on. The console log sink erases it before a log line and draws it again after, so on a
// terminal the log scrolls above the progress; off a terminal nothing is drawn.
#include <spdlog/common.h>

#include <cstdio>
#include <mutex>
#include <string>

namespace plugslam::runtime {

/// A redrawable line on a terminal stream (stderr for the CLI).
class StatusLine {
 public:
  /// Draws on `stream` when `terminal` is true; otherwise show() does nothing.
  StatusLine(std::FILE* stream, bool terminal);
  /// The CLI's line, on stderr (drawn only when stderr is a terminal).
  static StatusLine& console();

  /// True when the line is drawn (the stream is a terminal).
  bool terminal() const { return terminal_; }
  /// Replaces the line's text (cut to the terminal's width, so it never wraps).
  void show(const std::string& text);
  /// Erases the line; the next show() draws it again.
  void clear();
  /// Writes `text` (whole lines) above the line: erased first, drawn again after.
  void print(const std::string& text);
  /// Runs `write`, which writes whole lines to the stream, with the line erased around it.
  template <class F>
  void above(F&& write) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (drawn_) erase();
    write();
    if (drawn_) draw();
    std::fflush(stream_);
  }

 private:
  void erase();
  void draw();
  std::FILE* stream_;
  bool terminal_;
  std::mutex mutex_;
  std::string text_;
  bool drawn_ = false;
};

/// The console's log sink: colours on a terminal, and log lines above StatusLine::console().
spdlog::sink_ptr makeConsoleSink();

}  // namespace plugslam::runtime
