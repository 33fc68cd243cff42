#include "view/viewer.h"

#include <spdlog/sinks/base_sink.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <iostream>

#include "editor/config_editor.h"

namespace plugslam::runtime {

namespace {

// A viewer that connects late still gets this many of the last log lines.
constexpr uint64_t kLogLinesKept = 200;

// The end of a run waits at most this long for its viewers to receive what the byte budget held
// back: at the default 1 MB/s, 30 MB of maps (a large 2D session's grids), and not so long that
// a script waiting for the host to exit seems hung.
constexpr double kDrainSeconds = 30;

// The log, as the /log channel (foxglove.Log); lines from any thread. The last lines are latched
// in a ring of keys, so a late viewer sees what happened (ordered by their timestamps).
class LogChannel final : public spdlog::sinks::base_sink<std::mutex> {
 public:
  explicit LogChannel(ViewHub& hub)
      : hub_(&hub),
        channel_(hub.declare("/log", view::kindOf<view::LogLine>(), view::Latch::kPerKey)) {
    set_level(spdlog::level::info);
  }
  // After this, lines go nowhere. The sink stays in the logger (removing it would race with
  // threads logging meanwhile); it costs a lock per line.
  void detach() {
    std::lock_guard<std::mutex> lock(mutex_);
    hub_ = nullptr;
  }

 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    if (!hub_ || !hub_->wants(channel_)) return;
    view::LogLine line;
    line.stamp = std::chrono::duration<double>(msg.time.time_since_epoch()).count();
    switch (msg.level) {
      case spdlog::level::trace:
      case spdlog::level::debug: line.level = view::LogLine::Level::kDebug; break;
      case spdlog::level::warn: line.level = view::LogLine::Level::kWarning; break;
      case spdlog::level::err: line.level = view::LogLine::Level::kError; break;
      case spdlog::level::critical: line.level = view::LogLine::Level::kFatal; break;
      default: line.level = view::LogLine::Level::kInfo;
    }
    line.message.assign(msg.payload.data(), msg.payload.size());
    hub_->publish(channel_, view::Drawable(std::move(line)),
                 static_cast<int64_t>(lines_++ % kLogLinesKept));
  }
  void flush_() override {}

 private:
  ViewHub* hub_;
  int channel_;
  uint64_t lines_ = 0;
};

}  // namespace

bool ViewerOptions::enabled() const {
  return (serve_flag && serve_flag->count() > 0) || !record.empty();
}

void addViewerOptions(CLI::App& cmd, ViewerOptions& o, bool run_options) {
  o.serve_flag =
      cmd.add_option("--serve", o.serve,
                     "stream the run to viewers (Foxglove, Lichtblick, the built-in page) over the "
                     "Foxglove WebSocket protocol, with the page on the same port over HTTP; "
                     "[ADDR:PORT], default 127.0.0.1:8765, :0 for any free port")
          ->expected(0, 1);
  cmd.add_flag("--serve-remote", o.remote,
               "let --serve listen on a non-loopback address (whoever reaches it can pause the "
               "run and change its parameters)");
  cmd.add_option("--web-root", o.web_root, "serve the page from this folder instead of the installed one");
  cmd.add_option("--root", o.edit_root,
                 "the folder the page's configuration editor may save in (default: the current "
                 "folder); paths leading outside it are refused")
      ->check(CLI::ExistingDirectory);
  cmd.add_option("--record", o.record,
                 "record the viewer stream (every channel, full rate) into this MCAP file");
  cmd.add_option("--view-rate", o.rate,
                 "at most this many messages per second per streamed channel to live viewers "
                 "(recordings get every message)")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 1000.0));
  cmd.add_option("--view-budget", o.budget,
                 "at most this many MB per second to each live viewer for maps, grids, images and "
                 "scans (status, pose and frames always go first); what waits is replaced by "
                 "newer versions. 1: a Wi-Fi link to a robot; 0: no limit")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  if (!run_options) return;
  cmd.add_flag("--paused", o.paused,
               "with --serve: wait before the first frame until a viewer resumes or steps the run");
  cmd.add_flag("--keep-serving", o.keep_serving,
               "with --serve: when the run ends, keep serving its result until Ctrl-C");
}

Viewer::Viewer(const ViewerOptions& options) : options_(options) {
  if (!options_.enabled()) return;
  ViewHubOptions hub_options;
  hub_options.stream_rate = options_.rate;
  hub_ = std::make_unique<ViewHub>(hub_options);
  if (!options_.record.empty()) recorder_ = std::make_unique<McapRecorder>(*hub_, options_.record);
  stream_ = std::make_unique<ViewStream>();
  auto sink = std::make_shared<LogChannel>(*hub_);
  spdlog::default_logger()->sinks().push_back(sink);
  log_sink_ = sink;
  view::installPublisher(hub_.get());
}

Viewer::~Viewer() {
  try {
    stop();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  }
}

void Viewer::serve(ViewControl* control) {
  if (!hub_ || !options_.serve_flag || options_.serve_flag->count() == 0) return;
  ViewServerOptions o;
  parseServeAddress(options_.serve, o);
  o.allow_remote = options_.remote;
  o.budget = options_.budget * 1e6;
  o.web_root = findWebRoot(options_.web_root);
  if (!options_.edit_root.empty()) editor::setEditorRoot(options_.edit_root);
  server_ = std::make_unique<FoxgloveServer>(*hub_, control, o);
  server_->start();
  const std::string url = server_->url();
  const std::string page = "http" + url.substr(2);
  // On stdout, so a script (or a test) can read where to connect.
  std::cout << "serving " << url << " (page: " << page << "/"
            << (o.web_root.empty() ? ", not installed: connect Foxglove or Lichtblick" : "") << ")"
            << std::endl;
}

void Viewer::drain() {
  if (!hub_ || !server_) return;
  hub_->flush();
  const auto start = std::chrono::steady_clock::now();
  const bool all = server_->drain(kDrainSeconds);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (seconds > 0.5 || !all)
    spdlog::info("viewer: {:.1f} s sending viewers what --view-budget held back{}", seconds,
                 all ? "" : " (stopped waiting: a viewer reads too slowly)");
}

void Viewer::stop() {
  if (stopped_ || !hub_) return;
  stopped_ = true;
  view::installPublisher(nullptr);
  static_cast<LogChannel*>(log_sink_.get())->detach();
  hub_->flush();
  if (server_) {
    const ViewServerStats s = server_->stats();
    spdlog::info("viewer: {} client(s) served, {:.1f} MB sent, {} stream messages dropped for slow "
                 "clients, {} bad client messages answered",
                 s.connections, s.sent_bytes / 1e6, s.dropped, s.bad_messages);
  }
  server_.reset();
  if (recorder_) {
    auto recorder = std::move(recorder_);
    recorder->close();
  }
}

}  // namespace plugslam::runtime
