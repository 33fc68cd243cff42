#pragma once
// The viewer of one command (`run`, `shell`): its options (--serve, --record, ...), and the hub,
// stream, server, recorder and /log channel they switch on. The CLI keeps its hooks to this one
// object: it creates a Viewer, hands its observer to the run, and stops it at the end.
#include <memory>
#include <string>

#include "view/foxglove_server.h"
#include "view/mcap_recorder.h"
#include "view/view_hub.h"
#include "view/view_stream.h"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace plugslam::runtime {

/// The viewer's command-line options.
struct ViewerOptions {
  CLI::Option* serve_flag = nullptr;  ///< set when --serve was given
  std::string serve;                  ///< its ADDR:PORT ("" = the default)
  bool remote = false;                ///< --serve-remote
  std::string web_root;               ///< --web-root
  std::string edit_root;              ///< --root: where the config editor may save
  std::string record;                 ///< --record FILE.mcap
  double rate = ViewHubOptions{}.stream_rate;  ///< --view-rate
  double budget = ViewServerOptions{}.budget / 1e6;  ///< --view-budget [MB/s], 0: no limit
  bool paused = false;                ///< --paused: wait for a viewer before the first frame
  bool keep_serving = false;          ///< --keep-serving: serve the result until Ctrl-C
  /// True when anything was asked for.
  bool enabled() const;
};

/// Adds --serve, --serve-remote, --web-root, --record and --view-rate to `cmd`, and with
/// `run_options` --paused and --keep-serving (plugslam run).
void addViewerOptions(CLI::App& cmd, ViewerOptions& options, bool run_options = false);

/// The viewer of one command; inactive (and free) when no option asked for it.
class Viewer {
 public:
  /// Creates the hub, the stream and the recording, installs the publisher and the /log channel.
  explicit Viewer(const ViewerOptions& options);
  /// stop(), errors logged.
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  /// True when --serve or --record was given.
  bool active() const { return hub_ != nullptr; }
  /// Starts the server when --serve was given (`control` may be null); prints its address.
  void serve(ViewControl* control);
  /// The hub (only when active()).
  ViewHub& hub() { return *hub_; }
  /// The run's stream (only when active()).
  ViewStream& stream() { return *stream_; }
  /// The server, or null.
  FoxgloveServer* server() { return server_.get(); }
  /// The run ended (not interrupted): waits, at most kDrainSeconds, until the clients that still
  /// read got what waits for them (the end of a run held back by --view-budget).
  void drain();
  /// Removes the publisher, finishes the recording and stops the server; throws when the
  /// recording could not be completed.
  void stop();

 private:
  ViewerOptions options_;
  std::unique_ptr<ViewHub> hub_;
  std::unique_ptr<ViewStream> stream_;
  std::unique_ptr<McapRecorder> recorder_;
  std::unique_ptr<FoxgloveServer> server_;
  std::shared_ptr<void> log_sink_;
  bool stopped_ = false;
};

}  // namespace plugslam::runtime
