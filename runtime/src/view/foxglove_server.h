#pragma once
// The Foxglove WebSocket server of `plugslam run --serve` and `plugslam shell --serve`: one port
// for the WebSocket protocol (Foxglove, Lichtblick, our page) and plain HTTP (the page's files).
// Each connection has its own queue (view/client_queue.h) with one slot per channel (per local map
// on a per-map channel): a newer message replaces a waiting one, so a client that reads slowly
// gets the newest of everything and loses what was superseded (counted, told in a status message
// and on /status), never slowing the run. Bulk messages (maps, grids, images) go within a byte
// budget per connection. Client messages are parsed defensively: a bad one gets a status reply.
#include <cstdint>
#include <memory>
#include <string>

#include "view/view_control.h"
#include "view/view_hub.h"

namespace plugslam::runtime {

/// Settings of a server.
struct ViewServerOptions {
  std::string address = "127.0.0.1";  ///< where to listen
  uint16_t port = 8765;                ///< 0: any free port (see FoxgloveServer::port)
  bool allow_remote = false;           ///< refuse a non-loopback address unless set
  std::string web_root;                ///< directory of the page's files ("" = built-in notice)
  std::string name = "plugslam";       ///< serverInfo name
  /// Bytes per second each connection's bulk messages (maps, grids, images, scans) may take,
  /// <= 0: no limit. 1 MB/s: a Wi-Fi link to a robot, shared with whatever else it carries.
  double budget = 1e6;
  /// Seconds of the budget a connection may save up while idle: small messages leave at once,
  /// and no window of time gets more than the rate allows plus this.
  double burst_seconds = 0.05;
  size_t max_client_message = 1u << 20;  ///< larger client messages get an error status
  size_t max_connections = 32;         ///< further connections are refused (HTTP 503)
};

/// Counters of a server.
struct ViewServerStats {
  uint64_t connections = 0;    ///< WebSocket clients accepted so far
  uint64_t open = 0;           ///< connected now
  uint64_t dropped = 0;        ///< stream messages dropped for slow clients
  uint64_t sent_bytes = 0;     ///< WebSocket payload bytes written
  uint64_t bad_messages = 0;   ///< client messages answered with an error status
};

/// The server; start() binds and serves on its own thread until destroyed.
class FoxgloveServer final : public ViewReceiver {
 public:
  /// A server for `hub`; `control` (may be null: no parameters or services) outlives it.
  FoxgloveServer(ViewHub& hub, ViewControl* control, ViewServerOptions options);
  ~FoxgloveServer() override;
  FoxgloveServer(const FoxgloveServer&) = delete;
  FoxgloveServer& operator=(const FoxgloveServer&) = delete;

  /// Binds and starts serving; InputError when the address is refused or cannot be bound.
  void start();
  /// The bound port.
  uint16_t port() const;
  /// "ws://ADDRESS:PORT".
  std::string url() const;
  /// Counters so far.
  ViewServerStats stats() const;

  void channelAdded(const ViewChannel& channel) override;
  void deliver(const ViewMessage& message) override;
  bool wants(int channel) const override;
  /// True when some subscriber of `channel` has none of its messages waiting.
  bool ready(int channel) const override;

  /// Waits until every client that still reads got what waits for it, at most `max_seconds`;
  /// true when all did (the end of a run: its last map and graph reach the viewers).
  bool drain(double max_seconds);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// Parses "ADDR:PORT", ":PORT", "PORT" or "" (the default 127.0.0.1:8765) into `options`;
/// InputError when malformed.
void parseServeAddress(const std::string& text, ViewServerOptions& options);

/// The page's directory: `explicit_root` when set, else $PLUGSLAM_WEB_DIR, the installed
/// share/plugslam/web, the build tree's web/; "" when none holds an index.html.
std::string findWebRoot(const std::string& explicit_root);

}  // namespace plugslam::runtime
