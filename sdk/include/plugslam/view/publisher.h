#pragma once
// Publishing drawables on named channels. Modules and sinks hold a view::Channel<T> and publish
// into it; the runtime installs the Publisher behind them (its viewer server, its MCAP recorder).
// With nothing installed, asking a channel costs one atomic load; with a publisher, wanted() says
// whether a message published now would reach anyone, so a module builds drawables only then.
// Publish from the pipeline's (front-end) thread: the runtime installs and removes the publisher
// around whole runs, never during one.
#include <atomic>
#include <cstdint>
#include <string>

#include "plugslam/view/drawables.h"

namespace plugslam {
inline namespace abi_v1 {
namespace view {

/// How a channel keeps what it sent for receivers that arrive later.
enum class Latch {
  kNone,    ///< a stream: late receivers get the next message
  kLast,    ///< the last message is kept and sent to every new receiver
  kPerKey,  ///< the last message of each key is kept (e.g. one per local map): the set is sent
};

/// The receiving end of the stream, implemented by the runtime. Thread-safe; never blocks on a
/// receiver (slow receivers lose their oldest stream messages, counted).
class Publisher {
 public:
  virtual ~Publisher();
  /// Declares the channel `topic` carrying Drawable alternative `kind`; returns its id. The same
  /// topic declared again returns the same id (a different kind or latch throws InputError).
  virtual int declare(const std::string& topic, size_t kind, Latch latch) = 0;
  /// True when a message on `channel` published now would reach someone: a subscriber whose rate
  /// limit has passed, a recording, or (latched channels) the store kept for late subscribers.
  virtual bool wants(int channel) = 0;
  /// Publishes a message of the channel's kind; `key` is its slot on a kPerKey channel.
  virtual void publish(int channel, Drawable&& message, int64_t key) = 0;
};

/// Installs `publisher` for the whole process (nullptr removes it). The caller keeps it alive
/// until it is removed, and does neither while the pipeline runs.
void installPublisher(Publisher* publisher);

namespace detail {
extern std::atomic<Publisher*> g_publisher;
extern std::atomic<uint64_t> g_publisher_generation;
}  // namespace detail

/// A typed channel a module publishes on; declared with the installed publisher on first use.
template <class T>
class Channel {
 public:
  /// A channel called `topic` ("/scan/front"), kept as `latch` says.
  explicit Channel(std::string topic, Latch latch = Latch::kNone)
      : topic_(std::move(topic)), latch_(latch) {}
  /// The topic.
  const std::string& topic() const { return topic_; }
  /// True when a message published now would reach someone (false without a publisher).
  bool wanted() {
    Publisher* p = bind();
    return p && p->wants(id_);
  }
  /// Publishes `message` (dropped without a publisher); `key`: its slot on a kPerKey channel.
  void publish(T message, int64_t key = 0) {
    if (Publisher* p = bind()) p->publish(id_, Drawable(std::move(message)), key);
  }

 private:
  Publisher* bind() {
    Publisher* p = detail::g_publisher.load(std::memory_order_acquire);
    if (!p) return nullptr;
    const uint64_t generation = detail::g_publisher_generation.load(std::memory_order_acquire);
    if (generation != generation_) {
      id_ = p->declare(topic_, kindOf<T>(), latch_);
      generation_ = generation;
    }
    return p;
  }
  std::string topic_;
  Latch latch_;
  int id_ = -1;
  uint64_t generation_ = 0;  // of the publisher id_ was declared with (0: none)
};

}  // namespace view
}  // namespace abi_v1
}  // namespace plugslam
