// The server's network side, on Boost.Beast (HTTP and WebSocket on one port). Everything about a
// connection happens on the server's one I/O thread; the hub's worker and the host's threads only
// post work to it.
#include "view/foxglove_server.h"

#include <spdlog/spdlog.h>

#include <array>
#include <atomic>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/filesystem.hpp>
#include <chrono>
#include <deque>
#include <fstream>
#include <future>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "build_paths.h"
#include "plugslam/errors.h"
#include "plugslam/view/drawables.h"
#include "view/client_queue.h"

namespace plugslam::runtime {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;
namespace fs = boost::filesystem;

namespace {

// A client's WebSocket frames beyond this are not even read: the connection is closed with 1009
// (message too big). Below it and above max_client_message, the client gets an error status.
constexpr size_t kHardMessageLimit = 16u << 20;

// A write the socket has not taken for this long: the client stopped reading (the end of a run
// does not wait for it). A reading client over a link at the budget takes a second per MB.
constexpr auto kStalledWrite = std::chrono::seconds(5);

// The stream's urgent kinds: small, and what keeps a view live (where the robot is, the frames
// the rest is drawn in, the run's progress). They skip the byte budget (but count against it).
bool urgentKind(size_t kind) {
  return kind == view::kindOf<view::Status>() || kind == view::kindOf<view::PoseInFrame>() ||
         kind == view::kindOf<view::FrameTransforms>();
}

std::string contentType(const std::string& path) {
  static const std::map<std::string, std::string> types = {
      {".html", "text/html; charset=utf-8"}, {".js", "text/javascript; charset=utf-8"},
      {".mjs", "text/javascript; charset=utf-8"}, {".css", "text/css; charset=utf-8"},
      {".json", "application/json"}, {".map", "application/json"}, {".png", "image/png"},
      {".svg", "image/svg+xml"}, {".ico", "image/x-icon"}, {".wasm", "application/wasm"},
      {".txt", "text/plain; charset=utf-8"}, {".woff2", "font/woff2"}};
  const auto dot = path.rfind('.');
  if (dot != std::string::npos)
    if (auto it = types.find(path.substr(dot)); it != types.end()) return it->second;
  return "application/octet-stream";
}

bool isLoopback(const net::ip::address& a) {
  return a.is_loopback() || (a.is_v6() && a.to_v6().is_v4_mapped() &&
                             net::ip::make_address_v4(net::ip::v4_mapped, a.to_v6()).is_loopback());
}

// The notice served when the page is not installed.
std::string notice(const std::string& url) {
  return "<!doctype html><html><head><meta charset=\"utf-8\"><title>plugslam</title></head><body>"
         "<h1>plugslam viewer stream</h1><p>The built-in page is not installed with this host. "
         "Connect Foxglove or Lichtblick to <code>" +
         url + "</code> (Open connection, Foxglove WebSocket).</p></body></html>\n";
}

}  // namespace

struct FoxgloveServer::Impl {
  struct Session;

  ViewHub& hub;
  ViewControl* control;
  ViewServerOptions options;
  net::io_context ioc{1};
  tcp::acceptor acceptor{ioc};
  std::thread thread;
  std::string session_id;
  std::vector<foxglove::Service> services;
  int status_channel = -1;  // the /status channel, whose messages carry each client's drops

  // Read by other threads (wants): subscriber counts per channel id.
  mutable std::mutex mutex;
  std::map<int, int> subscribers;
  std::map<int, int> busy;  // per channel, the subscribed sessions with a message of it waiting
  std::map<int, int> in_transit;  // per channel, messages posted to the I/O thread, not yet queued
  ViewServerStats stats;

  // I/O thread only.
  std::vector<ViewChannel> channels;
  std::set<std::shared_ptr<Session>> sessions;
  size_t http_connections = 0;

  Impl(ViewHub& h, ViewControl* c, ViewServerOptions o) : hub(h), control(c), options(std::move(o)) {
    session_id = std::to_string(wallTimeNs());
    if (control) {
      services = control->services();
      for (size_t i = 0; i < services.size(); ++i) services[i].id = static_cast<uint32_t>(i + 1);
    }
  }

  void addSubscribers(int channel, int delta) {
    {
      std::lock_guard<std::mutex> lock(mutex);
      subscribers[channel] += delta;
      if (subscribers[channel] <= 0) subscribers.erase(channel);
    }
    hub.interestChanged();  // never under our mutex: the hub calls wants(), which takes it
  }
  void addBusy(int channel, int delta) {
    std::lock_guard<std::mutex> lock(mutex);
    busy[channel] += delta;
    if (busy[channel] <= 0) busy.erase(channel);
  }
  void count(uint64_t ViewServerStats::*field, uint64_t n = 1) {
    std::lock_guard<std::mutex> lock(mutex);
    stats.*field += n;
  }

  // ---- A WebSocket client ------------------------------------------------------------------
  struct Session : std::enable_shared_from_this<Session> {
    Impl& server;
    websocket::stream<beast::tcp_stream> ws;
    beast::flat_buffer buffer;
    std::string peer;
    bool open = false, writing = false, closed = false;
    ClientQueue queue;       // what waits: replies, then urgent, then bulk within the budget
    net::steady_timer timer;  // wakes write() when the budget allows the next bulk message
    std::chrono::steady_clock::time_point timer_due = std::chrono::steady_clock::time_point::max();
    std::chrono::steady_clock::time_point write_started{};
    std::set<int> busy;  // channels with a message waiting here (or being written)
    uint64_t dropped = 0, dropped_told = 0;
    std::chrono::steady_clock::time_point last_drop_notice{};
    std::map<uint32_t, int> subscriptions;  // subscription id -> channel
    std::map<int, uint32_t> by_channel;     // channel -> subscription id
    bool all_parameter_updates = false;
    std::set<std::string> parameter_updates;
    ClientMessage current;

    Session(Impl& s, tcp::socket&& socket, std::string who)
        : server(s),
          ws(std::move(socket)),
          peer(std::move(who)),
          queue(s.options.budget, s.options.budget * s.options.burst_seconds,
                std::chrono::steady_clock::now()),
          timer(ws.get_executor()) {}

    // Something still to send, and a socket that takes it.
    bool pending(std::chrono::steady_clock::time_point now) const {
      if (!open || closed || (queue.empty() && !writing)) return false;
      return !(writing && now - write_started > kStalledWrite);
    }

    // Tells the server whether a message of `channel` waits here (the hub builds a channel's
    // next message only when some subscriber took the last one).
    void syncBusy(int channel) {
      if (channel <= 0) return;
      const bool now_busy = queue.holds(channel) || (writing && current.channel == channel);
      if (now_busy == (busy.count(channel) > 0)) return;
      if (now_busy)
        busy.insert(channel);
      else
        busy.erase(channel);
      server.addBusy(channel, now_busy ? 1 : -1);
    }

    void start(http::request<http::string_body> request, std::string protocol) {
      ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
      ws.set_option(websocket::stream_base::decorator([protocol](websocket::response_type& res) {
        res.set(http::field::server, "plugslam");
        res.set(http::field::sec_websocket_protocol, protocol);
      }));
      ws.read_message_max(kHardMessageLimit);
      ws.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
        if (ec) return self->fail("handshake", ec);
        self->open = true;
        self->server.count(&ViewServerStats::connections);
        self->server.count(&ViewServerStats::open);
        spdlog::info("viewer: {} connected", self->peer);
        self->sendText(foxglove::serverInfo(self->server.options.name, self->server.session_id));
        self->sendText(foxglove::advertise(self->server.channels));
        if (!self->server.services.empty())
          self->sendText(foxglove::advertiseServices(self->server.services));
        self->read();
      });
    }

    void fail(const char* what, beast::error_code ec) {
      if (ec != websocket::error::closed && ec != net::error::operation_aborted &&
          ec != net::error::eof && ec != beast::error::timeout)
        spdlog::debug("viewer: {}: {}: {}", peer, what, ec.message());
      if (ec == websocket::error::message_too_big) server.count(&ViewServerStats::bad_messages);
      close();
    }

    void close() {
      if (closed) return;
      closed = true;
      if (open) {
        server.count(&ViewServerStats::open, static_cast<uint64_t>(-1));
        spdlog::info("viewer: {} left{}", peer,
                     dropped ? " (" + std::to_string(dropped) + " messages dropped)" : "");
      }
      for (int channel : busy) server.addBusy(channel, -1);
      busy.clear();
      for (const auto& [sub, channel] : subscriptions) server.addSubscribers(channel, -1);
      subscriptions.clear();
      by_channel.clear();
      beast::error_code cancelled;
      timer.cancel(cancelled);
      beast::error_code ignored;
      beast::get_lowest_layer(ws).socket().close(ignored);
      server.sessions.erase(shared_from_this());
    }

    void read() {
      ws.async_read(buffer, [self = shared_from_this()](beast::error_code ec, size_t n) {
        if (ec) return self->fail("read", ec);
        const bool text = self->ws.got_text();
        std::string data = beast::buffers_to_string(self->buffer.data());
        self->buffer.consume(n);
        self->handle(text, data);
        if (!self->closed) self->read();
      });
    }

    void reply(int level, const std::string& message, const std::string& id = "") {
      sendText(foxglove::status(level, message, id));
    }

    void handle(bool text, const std::string& data) {
      if (data.size() > server.options.max_client_message) {
        server.count(&ViewServerStats::bad_messages);
        return reply(2, "message of " + std::to_string(data.size()) + " bytes refused: the limit is " +
                            std::to_string(server.options.max_client_message));
      }
      try {
        auto message = text ? foxglove::parseText(data) : foxglove::parseBinary(data);
        std::visit([&](auto& m) { on(m); }, message);
      } catch (const foxglove::ProtocolError& e) {
        server.count(&ViewServerStats::bad_messages);
        reply(2, e.what());
      } catch (const std::exception& e) {
        server.count(&ViewServerStats::bad_messages);
        reply(2, std::string("request failed: ") + e.what());
      }
    }

    const ViewChannel* channel(uint32_t id) const {
      for (const auto& c : server.channels)
        if (c.id == static_cast<int>(id)) return &c;
      return nullptr;
    }

    void on(foxglove::Subscribe& s) {
      for (const auto& [sub, channel_id] : s.subscriptions) {
        const ViewChannel* c = channel(channel_id);
        if (!c) {
          server.count(&ViewServerStats::bad_messages);
          reply(2, "subscription " + std::to_string(sub) + ": no channel " +
                       std::to_string(channel_id));
          continue;
        }
        if (subscriptions.count(sub)) {
          server.count(&ViewServerStats::bad_messages);
          reply(2, "subscription id " + std::to_string(sub) + " is already in use");
          continue;
        }
        if (by_channel.count(c->id)) {
          server.count(&ViewServerStats::bad_messages);
          reply(1, "channel " + std::to_string(channel_id) + " (" + c->topic +
                       ") is already subscribed as " + std::to_string(by_channel[c->id]));
          continue;
        }
        subscriptions[sub] = c->id;
        by_channel[c->id] = sub;
        server.addSubscribers(c->id, 1);
        // A late subscriber gets the latched messages at once.
        if (c->latch != view::Latch::kNone)
          for (const auto& m : server.hub.latched(c->id)) push(m);
      }
    }

    void on(foxglove::Unsubscribe& u) {
      for (uint32_t sub : u.ids) {
        auto it = subscriptions.find(sub);
        if (it == subscriptions.end()) {
          server.count(&ViewServerStats::bad_messages);
          reply(1, "no subscription " + std::to_string(sub));
          continue;
        }
        const int channel_id = it->second;
        by_channel.erase(channel_id);
        subscriptions.erase(it);
        server.addSubscribers(channel_id, -1);
        // What was queued for it is not wanted any more.
        queue.removeChannel(channel_id);
        syncBusy(channel_id);
      }
    }

    // The reply to a parameter request, on the I/O thread: errors as statuses with the request's
    // id, then the values; after a set, the other clients that follow those parameters.
    ViewControl::ParametersDone parametersReply(const std::optional<std::string>& id, bool set) {
      return [this_server = &server, weak = weak_from_this(), id, set](
                 std::vector<foxglove::Parameter> values, std::vector<std::string> errors) {
        net::post(this_server->ioc, [this_server, weak, id, set, values = std::move(values),
                                     errors = std::move(errors)] {
          auto self = weak.lock();
          if (self && !self->closed) {
            for (const auto& e : errors) {
              this_server->count(&ViewServerStats::bad_messages);
              self->reply(2, e, id.value_or(""));
            }
            self->sendText(foxglove::parameterValues(values, id));
          }
          if (set) this_server->parametersChanged(values, self.get());
        });
      };
    }

    void on(foxglove::GetParameters& g) {
      if (!server.control) return reply(2, "this host has no parameters");
      server.control->getParameters(g.names, parametersReply(g.id, false));
    }

    void on(foxglove::SetParameters& s) {
      if (!server.control) return reply(2, "this host has no parameters");
      server.control->setParameters(s.parameters, parametersReply(s.id, true));
    }

    void on(foxglove::ParameterUpdates& p) {
      if (p.subscribe) {
        if (p.names.empty()) all_parameter_updates = true;
        parameter_updates.insert(p.names.begin(), p.names.end());
      } else {
        if (p.names.empty()) {
          all_parameter_updates = false;
          parameter_updates.clear();
        }
        for (const auto& n : p.names) parameter_updates.erase(n);
      }
    }

    void on(foxglove::ServiceCall& c) {
      const foxglove::Service* service = nullptr;
      for (const auto& s : server.services)
        if (s.id == c.service_id) service = &s;
      if (!service || !server.control) {
        server.count(&ViewServerStats::bad_messages);
        return sendText(foxglove::serviceCallFailure(c.service_id, c.call_id,
                                                     "no service " + std::to_string(c.service_id)));
      }
      if (c.encoding != "json") {
        server.count(&ViewServerStats::bad_messages);
        return sendText(foxglove::serviceCallFailure(
            c.service_id, c.call_id, "service requests are JSON, not '" + c.encoding.substr(0, 32) + "'"));
      }
      auto weak = weak_from_this();
      const uint32_t sid = c.service_id, cid = c.call_id;
      server.control->call(service->name, c.payload,
                           [this_server = &server, weak, sid, cid](bool ok, std::string message) {
                             net::post(this_server->ioc, [this_server, weak, sid, cid, ok,
                                                          message = std::move(message)] {
                               auto self = weak.lock();
                               if (!self || self->closed) return;
                               if (ok) {
                                 self->sendBinary(foxglove::serviceCallResponse(
                                     sid, cid, "json", foxglove::serviceResponse(message)));
                               } else {
                                 this_server->count(&ViewServerStats::bad_messages);
                                 self->sendText(foxglove::serviceCallFailure(sid, cid, message));
                               }
                             });
                           });
    }

    void on(foxglove::Ignored&) {}

    // ---- Output ------------------------------------------------------------------------------
    void sendText(std::string text) {
      queue.pushControl(
          ClientMessage{std::make_shared<const std::string>(std::move(text)), nullptr, false});
      write();
    }
    void sendBinary(std::string bytes) {
      queue.pushControl(
          ClientMessage{std::make_shared<const std::string>(std::move(bytes)), nullptr, true});
      write();
    }

    // Queues a hub message for this client if it subscribed to its channel.
    void push(const ViewMessage& m) {
      auto it = by_channel.find(m.channel);
      if (it == by_channel.end() || closed) return;
      auto payload = m.payload;
      if (m.channel == server.status_channel && !payload->empty() && payload->back() == '}') {
        // Each client sees its own drops on /status.
        std::string patched = payload->substr(0, payload->size() - 1);
        patched += ",\"dropped\":" + std::to_string(dropped) +
                   ",\"dropped_total\":" + std::to_string(server.totalDropped()) + "}";
        payload = std::make_shared<const std::string>(std::move(patched));
      }
      const ViewChannel* c = channel(static_cast<uint32_t>(m.channel));
      if (!c) return;
      ClientMessage o{
          std::make_shared<const std::string>(foxglove::messageDataHeader(it->second, m.log_time)),
          payload, true, m.channel, m.key};
      const auto lane = urgentKind(c->kind) ? ClientQueue::Lane::kUrgent : ClientQueue::Lane::kBulk;
      // A newer message took the waiting one's place: for a local map's slot that is its newer
      // version, for any other channel a message this client never gets (counted).
      if (queue.push(std::move(o), lane, std::chrono::steady_clock::now()) &&
          c->latch != view::Latch::kPerKey)
        noteDropped(1);
      syncBusy(m.channel);
      write();
    }

    void noteDropped(uint64_t lost) {
      dropped += lost;
      server.count(&ViewServerStats::dropped, lost);
      const auto now = std::chrono::steady_clock::now();
      if (now - last_drop_notice > std::chrono::seconds(5)) {
        last_drop_notice = now;
        reply(1, std::to_string(dropped - dropped_told) +
                     " messages dropped: this client reads slower than the stream (" +
                     std::to_string(dropped) + " so far)");
        dropped_told = dropped;
      }
    }

    // Wakes write() at `due` (the earliest of the waits asked for).
    void wakeAt(std::chrono::steady_clock::time_point due) {
      if (due == std::chrono::steady_clock::time_point::max() || due >= timer_due) return;
      timer_due = due;
      timer.expires_at(due);
      timer.async_wait([self = shared_from_this()](beast::error_code ec) {
        if (ec) return;  // cancelled: re-armed earlier, or closed
        self->timer_due = std::chrono::steady_clock::time_point::max();
        self->write();
      });
    }

    void write() {
      if (!open || writing || closed) return;
      const auto now = std::chrono::steady_clock::now();
      auto next = queue.pop(now);
      if (!next) return wakeAt(queue.nextDue(now));
      current = std::move(*next);
      write_started = now;
      writing = true;
      ws.binary(current.binary);
      std::array<net::const_buffer, 2> buffers{
          net::buffer(*current.head),
          current.payload ? net::buffer(*current.payload) : net::const_buffer()};
      ws.async_write(buffers, [self = shared_from_this()](beast::error_code ec, size_t n) {
        self->writing = false;
        const int written = self->current.channel;
        self->current = ClientMessage{};
        if (ec) return self->fail("write", ec);
        self->server.count(&ViewServerStats::sent_bytes, n);
        self->syncBusy(written);
        self->write();
      });
    }
  };

  uint64_t totalDropped() {
    std::lock_guard<std::mutex> lock(mutex);
    return stats.dropped;
  }

  void parametersChanged(const std::vector<foxglove::Parameter>& values, Session* except) {
    for (const auto& s : sessions) {
      if (s.get() == except || s->closed) continue;
      std::vector<foxglove::Parameter> wanted;
      for (const auto& v : values)
        if (s->all_parameter_updates || s->parameter_updates.count(v.name)) wanted.push_back(v);
      if (!wanted.empty()) s->sendText(foxglove::parameterValues(wanted, std::nullopt));
    }
  }

  // ---- HTTP: the page's files, or the upgrade to WebSocket ---------------------------------
  struct HttpSession : std::enable_shared_from_this<HttpSession> {
    Impl& server;
    beast::tcp_stream stream;
    beast::flat_buffer buffer;
    std::optional<http::request_parser<http::string_body>> parser;
    std::string peer;

    HttpSession(Impl& s, tcp::socket&& socket, std::string who)
        : server(s), stream(std::move(socket)), peer(std::move(who)) {}

    void read() {
      parser.emplace();
      parser->header_limit(16 * 1024);
      parser->body_limit(64 * 1024);
      stream.expires_after(std::chrono::seconds(30));
      http::async_read(stream, buffer, *parser,
                       [self = shared_from_this()](beast::error_code ec, size_t) {
                         if (ec) return self->done();
                         self->handle(self->parser->release());
                       });
    }

    void done() {
      beast::error_code ignored;
      stream.socket().shutdown(tcp::socket::shutdown_both, ignored);
      --server.http_connections;
    }

    template <class Body>
    void send(http::response<Body>&& res) {
      auto sp = std::make_shared<http::response<Body>>(std::move(res));
      http::async_write(stream, *sp, [self = shared_from_this(), sp](beast::error_code ec, size_t) {
        if (ec || sp->need_eof()) return self->done();
        self->read();
      });
    }

    http::response<http::string_body> text(const http::request<http::string_body>& req,
                                           http::status status, const std::string& body,
                                           const std::string& type = "text/plain; charset=utf-8") {
      http::response<http::string_body> res{status, req.version()};
      res.set(http::field::server, "plugslam");
      res.set(http::field::content_type, type);
      res.keep_alive(req.keep_alive());
      res.body() = req.method() == http::verb::head ? std::string() : body;
      res.prepare_payload();
      if (req.method() == http::verb::head) res.content_length(body.size());
      return res;
    }

    void handle(http::request<http::string_body> req) {
      if (websocket::is_upgrade(req)) return upgrade(std::move(req));
      if (req.method() != http::verb::get && req.method() != http::verb::head)
        return send(text(req, http::status::method_not_allowed, "only GET and HEAD\n"));
      std::string target(req.target());
      if (const auto q = target.find_first_of("?#"); q != std::string::npos) target.resize(q);
      if (target.empty() || target[0] != '/' || target.find("..") != std::string::npos ||
          target.find('\\') != std::string::npos || target.find('\0') != std::string::npos ||
          target.find('%') != std::string::npos)
        return send(text(req, http::status::bad_request, "bad path\n"));
      if (target == "/") target = "/index.html";
      if (server.options.web_root.empty()) {
        if (target == "/index.html")
          return send(text(req, http::status::ok, notice(server.url()), "text/html; charset=utf-8"));
        return send(text(req, http::status::not_found, "not found\n"));
      }
      // The file must resolve inside the root (a symlink leading out is refused).
      boost::system::error_code ec;
      const fs::path root = fs::canonical(server.options.web_root, ec);
      const fs::path file = fs::canonical(fs::path(server.options.web_root) / target.substr(1), ec);
      const std::string r = root.string() + "/";
      if (ec || file.string().compare(0, r.size(), r) != 0 || !fs::is_regular_file(file, ec))
        return send(text(req, http::status::not_found, "not found\n"));
      http::file_body::value_type body;
      beast::error_code fec;
      body.open(file.string().c_str(), beast::file_mode::scan, fec);
      if (fec) return send(text(req, http::status::not_found, "not found\n"));
      const auto size = body.size();
      if (req.method() == http::verb::head) {
        http::response<http::empty_body> res{http::status::ok, req.version()};
        res.set(http::field::server, "plugslam");
        res.set(http::field::content_type, contentType(file.string()));
        res.content_length(size);
        res.keep_alive(req.keep_alive());
        return send(std::move(res));
      }
      http::response<http::file_body> res{std::piecewise_construct, std::make_tuple(std::move(body)),
                                          std::make_tuple(http::status::ok, req.version())};
      res.set(http::field::server, "plugslam");
      res.set(http::field::content_type, contentType(file.string()));
      res.set(http::field::cache_control, "no-cache");
      res.content_length(size);
      res.keep_alive(req.keep_alive());
      send(std::move(res));
    }

    void upgrade(http::request<http::string_body> req) {
      // Echo the first subprotocol the client offers that we speak.
      std::string chosen;
      std::stringstream offered{std::string(req[http::field::sec_websocket_protocol])};
      std::string item;
      while (chosen.empty() && std::getline(offered, item, ',')) {
        const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
        if (b == std::string::npos) continue;
        item = item.substr(b, e - b + 1);
        for (const char* p : foxglove::kSubprotocols)
          if (item == p) chosen = p;
      }
      if (chosen.empty()) {
        return send(text(req, http::status::bad_request,
                         "offer the WebSocket subprotocol foxglove.websocket.v1 or "
                         "foxglove.sdk.v1\n"));
      }
      if (server.sessions.size() >= server.options.max_connections)
        return send(text(req, http::status::service_unavailable, "too many viewers connected\n"));
      --server.http_connections;
      stream.expires_never();
      auto session = std::make_shared<Session>(server, stream.release_socket(), peer);
      server.sessions.insert(session);
      session->start(std::move(req), chosen);
    }
  };

  void accept() {
    acceptor.async_accept(ioc, [this](beast::error_code ec, tcp::socket socket) {
      if (ec == net::error::operation_aborted) return;
      if (!ec) {
        boost::system::error_code pe;
        const auto ep = socket.remote_endpoint(pe);
        const std::string who = pe ? "a client" : ep.address().to_string() + ":" + std::to_string(ep.port());
        if (http_connections + sessions.size() >= 4 * options.max_connections) {
          socket.close(pe);  // a flood of half-open connections
        } else {
          ++http_connections;
          std::make_shared<HttpSession>(*this, std::move(socket), who)->read();
        }
      }
      accept();
    });
  }

  std::string url() const {
    const auto ep = acceptor.local_endpoint();
    const std::string host = ep.address().is_v6() ? "[" + ep.address().to_string() + "]"
                                                  : ep.address().to_string();
    return "ws://" + host + ":" + std::to_string(ep.port());
  }
};

FoxgloveServer::FoxgloveServer(ViewHub& hub, ViewControl* control, ViewServerOptions options)
    : impl_(std::make_unique<Impl>(hub, control, std::move(options))) {}

FoxgloveServer::~FoxgloveServer() {
  impl_->hub.detach(this);
  net::post(impl_->ioc, [impl = impl_.get()] {
    beast::error_code ignored;
    impl->acceptor.close(ignored);
    auto sessions = impl->sessions;
    for (const auto& s : sessions) s->close();
    impl->ioc.stop();
  });
  if (impl_->thread.joinable()) impl_->thread.join();
}

void FoxgloveServer::start() {
  auto& o = impl_->options;
  boost::system::error_code ec;
  const auto address = net::ip::make_address(o.address, ec);
  if (ec) throw InputError("--serve: '" + o.address + "' is not an IP address");
  if (!isLoopback(address) && !o.allow_remote)
    throw InputError("--serve " + o.address +
                     ": the viewer server listens on loopback only unless --serve-remote is "
                     "given (anyone who can reach the port can pause the run and change its "
                     "parameters)");
  const tcp::endpoint endpoint(address, o.port);
  auto& acceptor = impl_->acceptor;
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(net::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(net::socket_base::max_listen_connections, ec);
  if (ec)
    throw InputError("--serve: cannot listen on " + o.address + ":" + std::to_string(o.port) +
                     ": " + ec.message() + (ec == net::error::address_in_use
                                                ? " (another server is there; pick another port "
                                                  "or :0 for any free one)"
                                                : ""));
  impl_->hub.attach(this);
  impl_->accept();
  impl_->thread = std::thread([impl = impl_.get()] {
    for (;;) {
      try {
        impl->ioc.run();
        return;
      } catch (const std::exception& e) {
        // A handler that throws must not take the run down: log it and serve on.
        spdlog::error("viewer server: {}", e.what());
      }
    }
  });
}

uint16_t FoxgloveServer::port() const { return impl_->acceptor.local_endpoint().port(); }
std::string FoxgloveServer::url() const { return impl_->url(); }

ViewServerStats FoxgloveServer::stats() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

void FoxgloveServer::channelAdded(const ViewChannel& channel) {
  net::post(impl_->ioc, [impl = impl_.get(), channel] {
    if (channel.kind == view::kindOf<view::Status>()) impl->status_channel = channel.id;
    impl->channels.push_back(channel);
    for (const auto& s : impl->sessions)
      if (s->open && !s->closed) s->sendText(foxglove::advertise({channel}));
  });
}

void FoxgloveServer::deliver(const ViewMessage& message) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    ++impl_->in_transit[message.channel];
  }
  net::post(impl_->ioc, [impl = impl_.get(), message] {
    auto sessions = impl->sessions;
    for (const auto& s : sessions) s->push(message);
    std::lock_guard<std::mutex> lock(impl->mutex);
    if (--impl->in_transit[message.channel] <= 0) impl->in_transit.erase(message.channel);
  });
}

bool FoxgloveServer::wants(int channel) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->subscribers.count(channel) > 0;
}

bool FoxgloveServer::ready(int channel) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  const auto s = impl_->subscribers.find(channel);
  if (s == impl_->subscribers.end() || impl_->in_transit.count(channel)) return false;
  const auto b = impl_->busy.find(channel);
  return b == impl_->busy.end() || b->second < s->second;
}

bool FoxgloveServer::drain(double max_seconds) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(max_seconds));
  for (;;) {
    // Asked on the I/O thread, which owns the sessions.
    auto answer = std::make_shared<std::promise<bool>>();
    auto waiting = answer->get_future();
    net::post(impl_->ioc, [impl = impl_.get(), answer] {
      const auto now = Clock::now();
      bool any = false;
      for (const auto& s : impl->sessions) any = any || s->pending(now);
      answer->set_value(any);
    });
    if (waiting.wait_for(std::chrono::seconds(5)) != std::future_status::ready) return false;
    if (!waiting.get()) return true;
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

void parseServeAddress(const std::string& text, ViewServerOptions& options) {
  if (text.empty()) return;
  std::string host = options.address, port = text;
  const auto colon = text.rfind(':');
  if (colon != std::string::npos) {
    host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (host.size() >= 2 && host.front() == '[' && host.back() == ']')
      host = host.substr(1, host.size() - 2);
    if (host.empty()) host = options.address;
  } else if (text.find_first_not_of("0123456789") != std::string::npos) {
    host = text;  // an address alone keeps the default port
    port = std::to_string(options.port);
  }
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos ||
      std::stoul(port) > 65535)
    throw InputError("--serve '" + text + "': expected ADDR:PORT (e.g. 127.0.0.1:8765, :0 for "
                     "any free port)");
  options.address = host;
  options.port = static_cast<uint16_t>(std::stoul(port));
}

std::string findWebRoot(const std::string& explicit_root) {
  auto holds = [](const fs::path& d) {
    boost::system::error_code ec;
    return fs::is_regular_file(d / "index.html", ec);
  };
  if (!explicit_root.empty()) {
    if (!holds(explicit_root))
      throw InputError("--web-root '" + explicit_root + "' holds no index.html");
    return explicit_root;
  }
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("PLUGSLAM_WEB_DIR")) candidates.emplace_back(env);
  const fs::path exe = boost::dll::program_location();
  candidates.push_back(exe.parent_path().parent_path() / "share" / "plugslam" / "web");
  candidates.push_back(fs::path(build_paths::installDataDir()) / "web");
  candidates.push_back(fs::path(build_paths::buildWebDir()));
  for (const auto& c : candidates)
    if (holds(c)) return c.string();
  return "";
}

}  // namespace plugslam::runtime
