#pragma once
// What one viewer connection has left to send, and when it may send it. Three lanes: protocol
// replies (never dropped, first), urgent stream messages (status, pose, frames: small, and what
// keeps the view live) and bulk ones (maps, grids, trajectory, images, scans). In the two stream
// lanes a newer message of the same channel (and key, on a per-local-map channel) replaces the
// waiting one in its place, so a slow link never queues stale maps or images, and the queue
// never holds more than one message per (channel, key). Bulk messages go out within a byte budget
// per second that starts empty; urgent ones are never held back but are counted against it.
// No network here: the server's I/O thread owns one queue per connection (tests drive it alone).
#include <chrono>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace plugslam::runtime {

/// A token bucket of bytes per second that starts empty.
class ByteBudget {
 public:
  using Clock = std::chrono::steady_clock;
  /// `rate` bytes per second (<= 0: no limit); at most `burst` bytes saved up while nothing
  /// waits; empty at `start`.
  ByteBudget(double rate, double burst, Clock::time_point start);
  /// Saves up until `now`, with a message of `waiting` bytes held back meanwhile (0: none): the
  /// balance grows to the larger of the burst and that message, never further.
  void advance(Clock::time_point now, size_t waiting);
  /// True when `bytes` may be sent now.
  bool allows(size_t bytes) const { return rate_ <= 0 || tokens_ >= static_cast<double>(bytes); }
  /// Counts `bytes` sent (the balance may go negative: urgent messages borrow).
  void spend(size_t bytes);
  /// When `bytes` will be allowed, after advance(now), if nothing else is spent meanwhile.
  Clock::time_point when(size_t bytes, Clock::time_point now) const;
  /// False when there is no limit.
  bool limited() const { return rate_ > 0; }

 private:
  double rate_, burst_;
  double tokens_ = 0;
  Clock::time_point last_;
};

/// One message waiting on a connection.
struct ClientMessage {
  std::shared_ptr<const std::string> head;     ///< text message, or a binary header
  std::shared_ptr<const std::string> payload;  ///< binary payload after the header, or null
  bool binary = false;                         ///< a binary WebSocket message
  int channel = 0;                             ///< the hub's channel (0: a protocol reply)
  int64_t key = 0;                             ///< its key on a per-key channel
  /// Bytes on the wire (the WebSocket frame header aside).
  size_t size() const { return (head ? head->size() : 0) + (payload ? payload->size() : 0); }
};

/// A connection's outgoing queue; not thread-safe (the server's I/O thread owns it).
class ClientQueue {
 public:
  using Clock = ByteBudget::Clock;
  /// Which lane a stream message takes.
  enum class Lane { kUrgent, kBulk };
  /// A queue whose bulk lane goes at `budget` bytes per second (<= 0: no limit), saving up at most
  /// `burst` bytes while idle; the budget starts empty at `start`.
  ClientQueue(double budget, double burst, Clock::time_point start);

  /// A protocol reply: kept in order, never replaced or dropped.
  void pushControl(ClientMessage message);
  /// A stream message arriving at `now`; it replaces a waiting one of the same (channel, key),
  /// keeping its place. Returns true when it replaced one (the older one is gone).
  bool push(ClientMessage message, Lane lane, Clock::time_point now);
  /// The next message to write at `now`: replies, then urgent, then bulk when the budget allows.
  std::optional<ClientMessage> pop(Clock::time_point now);
  /// When pop() will next give something while nothing is added (max(): it never will).
  Clock::time_point nextDue(Clock::time_point now);
  /// True when a stream message of `channel` waits.
  bool holds(int channel) const;
  /// Removes every waiting message of `channel` (an unsubscription); returns how many.
  size_t removeChannel(int channel);
  /// Messages waiting.
  size_t size() const;
  /// True when nothing waits.
  bool empty() const { return size() == 0; }
  /// Bytes waiting.
  size_t bytes() const { return bytes_; }

 private:
  // Slots in order of their first arrival, found by (channel, key).
  struct Slots {
    std::list<ClientMessage> order;
    std::map<std::pair<int, int64_t>, std::list<ClientMessage>::iterator> index;
  };
  ClientMessage take(Slots& slots);
  void advance(Clock::time_point now);
  std::list<ClientMessage> control_;
  Slots urgent_, bulk_;
  ByteBudget budget_;
  size_t bytes_ = 0;
};

}  // namespace plugslam::runtime
