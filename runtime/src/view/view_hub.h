#pragma once
// The runtime's side of the viewer stream: the Publisher that modules and the run's ViewStream
// publish into, and the fan-out to receivers (the Foxglove WebSocket server, the MCAP recorder).
// Publishing only hands a drawable to the hub (a short lock); the hub's worker thread encodes it
// (JSON, the @foxglove/schemas layouts) once and delivers it, so the pipeline never waits for a
// receiver. Latched channels keep their last message (per key) for receivers that come later.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "plugslam/view/publisher.h"

namespace plugslam::runtime {

/// A channel as receivers see it.
struct ViewChannel {
  int id = 0;                 ///< 1, 2, ... in declaration order
  std::string topic;          ///< "/scan/front"
  size_t kind = 0;            ///< view::Drawable alternative
  view::Latch latch = view::Latch::kNone;
  std::string schema_name;    ///< "foxglove.PointCloud"
  std::string schema;         ///< JSON schema text
};

/// One encoded message.
struct ViewMessage {
  int channel = 0;           ///< ViewChannel::id
  int64_t key = 0;           ///< its slot on a kPerKey channel
  uint64_t log_time = 0;     ///< ns since the epoch (wall time when published)
  std::shared_ptr<const std::string> payload;  ///< JSON
  bool latched = false;      ///< from a latched channel (never dropped for a newer stream message)
};

/// Receives what the hub delivers; called on the hub's worker thread, must not block.
class ViewReceiver {
 public:
  virtual ~ViewReceiver();
  /// A channel was declared (also called, at attach, for the channels declared before).
  virtual void channelAdded(const ViewChannel& channel) = 0;
  /// A message to deliver.
  virtual void deliver(const ViewMessage& message) = 0;
  /// True when this receiver takes every message of `channel` now (a subscriber, a recording).
  virtual bool wants(int channel) const = 0;
  /// True for receivers that take every message at full rate (recordings).
  virtual bool fullRate() const { return false; }
  /// True when the receiver took the last message of `channel` it wanted (nothing of it waits
  /// to be sent): a live stream channel's next message is built only for a ready receiver.
  virtual bool ready(int channel) const {
    (void)channel;
    return true;
  }
};

/// Settings of the hub.
struct ViewHubOptions {
  /// Stream channels reach live receivers at most this often [Hz]: 10 Hz looks continuous for a
  /// robot moving a couple of metres per second, and a faster replay would only fill the link.
  double stream_rate = 10.0;
  /// Camera images reach live receivers at most this often [Hz] (and at most stream_rate): a
  /// camera panel shows what the robot sees, which a person follows at 5 Hz as well as at 10,
  /// and images are most of the stream's bytes and of its work (shrinking, JPEG).
  double image_rate = 5.0;
  /// Messages waiting for the worker at most; beyond, the oldest stream message is dropped.
  size_t inbox_capacity = 512;
};

/// The viewer stream's hub; thread-safe.
class ViewHub final : public view::Publisher {
 public:
  explicit ViewHub(ViewHubOptions options = {});
  ~ViewHub() override;
  ViewHub(const ViewHub&) = delete;
  ViewHub& operator=(const ViewHub&) = delete;

  int declare(const std::string& topic, size_t kind, view::Latch latch) override;
  bool wants(int channel) override;
  void publish(int channel, view::Drawable&& message, int64_t key) override;

  /// Adds a receiver; it gets channelAdded for every channel so far. Kept until removed.
  void attach(ViewReceiver* receiver);
  /// Removes a receiver; after this returns, the worker no longer calls it.
  void detach(ViewReceiver* receiver);
  /// The channels so far.
  std::vector<ViewChannel> channels() const;
  /// The latched messages of `channel` (encoded now if they were not yet), oldest key first.
  std::vector<ViewMessage> latched(int channel);
  /// Receivers call this when what they want changed (a subscription came or went).
  void interestChanged();
  /// Forgets every latched message (a new run starts: its maps are not the last run's).
  void clearLatched();
  /// Waits until every message published so far was delivered (tests, the end of a run).
  void flush();
  /// Messages dropped because the worker fell behind (the inbox was full, or a newer message of
  /// a live stream channel replaced one still waiting in it).
  uint64_t dropped() const;

 private:
  struct Item {
    int channel;
    int64_t key;
    uint64_t log_time;
    std::shared_ptr<const view::Drawable> drawable;
    bool live;  // within the channel's live rate
  };
  struct Latched {
    std::shared_ptr<const view::Drawable> drawable;
    std::shared_ptr<const std::string> payload;  // encoded lazily
    uint64_t log_time = 0;
  };
  struct Channel {
    ViewChannel info;
    std::chrono::steady_clock::time_point next_live{};
    std::chrono::steady_clock::duration live_period{};  // between live messages
    int in_hub = 0;            // live messages of it in the inbox or being delivered
    bool pending = false;      // kLast: the stored message was not delivered live yet (rate)
    bool live_wanted = false;  // some live receiver wants it (cached by the worker)
    bool full_wanted = false;  // a full-rate receiver wants it
    std::map<int64_t, Latched> latched;
  };
  void run();
  void refreshWants();  // under mutex_
  bool liveReady(const Channel& c) const;  // under mutex_: a live receiver took the last one
  std::shared_ptr<const std::string> encode(const Channel& c, const view::Drawable& d) const;

  ViewHubOptions options_;
  mutable std::mutex mutex_;
  std::condition_variable cv_, idle_cv_;
  std::deque<Channel> channels_;  // index = id - 1; a deque: references stay valid as it grows
  std::map<std::string, int> by_topic_;
  std::vector<ViewReceiver*> receivers_;
  std::deque<Item> inbox_;
  uint64_t dropped_ = 0;
  bool busy_ = false;  // the worker is delivering an item
  bool stop_ = false;
  std::thread worker_;
  std::mutex deliver_mutex_;  // held while the worker calls receivers (detach waits on it)
};

/// Wall time now, ns since the epoch.
uint64_t wallTimeNs();

}  // namespace plugslam::runtime
