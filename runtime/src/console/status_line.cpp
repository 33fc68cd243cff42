#include "console/status_line.h"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <sys/ioctl.h>
#include <unistd.h>

namespace plugslam::runtime {

namespace {

// Erase from the cursor to the end of the line (ANSI EL); every terminal emulator has it.
constexpr const char* kEraseLine = "\033[K";

size_t terminalWidth(std::FILE* stream) {
  winsize ws{};
  if (::ioctl(::fileno(stream), TIOCGWINSZ, &ws) == 0 && ws.ws_col > 0) return ws.ws_col;
  return 80;
}

// Log lines go through the colour sink with the status line erased around each of them.
class ConsoleSink final : public spdlog::sinks::sink {
 public:
  ConsoleSink() : inner_(std::make_shared<spdlog::sinks::stderr_color_sink_mt>()) {}
  void log(const spdlog::details::log_msg& msg) override {
    StatusLine::console().above([&] {
      inner_->log(msg);
      inner_->flush();
    });
  }
  void flush() override { inner_->flush(); }
  void set_pattern(const std::string& pattern) override { inner_->set_pattern(pattern); }
  void set_formatter(std::unique_ptr<spdlog::formatter> formatter) override {
    inner_->set_formatter(std::move(formatter));
  }

 private:
  spdlog::sink_ptr inner_;
};

}  // namespace

StatusLine::StatusLine(std::FILE* stream, bool terminal) : stream_(stream), terminal_(terminal) {}

StatusLine& StatusLine::console() {
  static StatusLine line(stderr, ::isatty(STDERR_FILENO) == 1);
  return line;
}

void StatusLine::erase() { std::fprintf(stream_, "\r%s", kEraseLine); }

void StatusLine::draw() {
  const size_t width = terminalWidth(stream_);
  // One column short of the width: a line that fills it moves some terminals to the next row.
  const std::string shown = text_.size() < width ? text_ : text_.substr(0, width - 1);
  std::fprintf(stream_, "\r%s%s", shown.c_str(), kEraseLine);
}

void StatusLine::show(const std::string& text) {
  if (!terminal_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  text_ = text;
  drawn_ = true;
  draw();
  std::fflush(stream_);
}

void StatusLine::clear() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (drawn_) erase();
  drawn_ = false;
  std::fflush(stream_);
}

void StatusLine::print(const std::string& text) {
  above([&] { std::fputs(text.c_str(), stream_); });
}

spdlog::sink_ptr makeConsoleSink() { return std::make_shared<ConsoleSink>(); }

}  // namespace plugslam::runtime
