#include "view/view_hub.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "plugslam/errors.h"
#include "view/view_json.h"

namespace plugslam::runtime {

using Clock = std::chrono::steady_clock;

ViewReceiver::~ViewReceiver() = default;

uint64_t wallTimeNs() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::system_clock::now().time_since_epoch())
                                   .count());
}

ViewHub::ViewHub(ViewHubOptions options) : options_(options) {
  if (!(options_.stream_rate > 0)) options_.stream_rate = 10.0;
  if (!(options_.image_rate > 0)) options_.image_rate = options_.stream_rate;
  worker_ = std::thread([this] { run(); });
}

ViewHub::~ViewHub() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  worker_.join();
}

int ViewHub::declare(const std::string& topic, size_t kind, view::Latch latch) {
  ViewChannel info;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = by_topic_.find(topic); it != by_topic_.end()) {
      const ViewChannel& c = channels_[static_cast<size_t>(it->second - 1)].info;
      if (c.kind != kind || c.latch != latch)
        throw InputError("viewer channel '" + topic + "' was declared with another type");
      return c.id;
    }
    info.id = static_cast<int>(channels_.size()) + 1;
    info.topic = topic;
    info.kind = kind;
    info.latch = latch;
    info.schema_name = schemaName(kind);
    info.schema = jsonSchema(kind);
    channels_.emplace_back();
    channels_.back().info = info;
    const double rate = kind == view::kindOf<view::CameraImage>()
                            ? std::min(options_.stream_rate, options_.image_rate)
                            : options_.stream_rate;
    channels_.back().live_period =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate));
    by_topic_[topic] = info.id;
    refreshWants();  // a recording wants it from its first message
  }
  // Receivers learn of the channel on the worker thread, in order with the messages.
  std::lock_guard<std::mutex> deliver(deliver_mutex_);
  std::vector<ViewReceiver*> receivers;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    receivers = receivers_;
  }
  for (ViewReceiver* r : receivers) r->channelAdded(info);
  return info.id;
}

bool ViewHub::wants(int id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (id < 1 || id > static_cast<int>(channels_.size())) return false;
  const Channel& c = channels_[static_cast<size_t>(id - 1)];
  if (c.info.latch != view::Latch::kNone) return true;  // kept for later receivers
  // A live stream message is built only when the last one left the hub and some receiver took
  // it: no work on frames nobody would get.
  return c.full_wanted ||
         (c.live_wanted && Clock::now() >= c.next_live && c.in_hub == 0 && liveReady(c));
}

bool ViewHub::liveReady(const Channel& c) const {
  for (const ViewReceiver* r : receivers_)
    if (!r->fullRate() && r->wants(c.info.id) && r->ready(c.info.id)) return true;
  return false;
}

void ViewHub::publish(int id, view::Drawable&& message, int64_t key) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (id < 1 || id > static_cast<int>(channels_.size())) return;
  Channel& c = channels_[static_cast<size_t>(id - 1)];
  if (message.index() != c.info.kind) return;  // a module publishing the wrong type: ignored
  const auto now = Clock::now();
  bool live = false;
  if (c.live_wanted) {
    // Per-key latched messages (one per local map) are sparse by nature: never rate-limited.
    // A stream message goes live only when a receiver took the channel's last one.
    live = c.info.latch == view::Latch::kPerKey ||
           (now >= c.next_live && (c.info.latch != view::Latch::kNone || liveReady(c)));
    if (live && c.info.latch != view::Latch::kPerKey) c.next_live = now + c.live_period;
  }
  auto drawable = std::make_shared<const view::Drawable>(std::move(message));
  const uint64_t t = wallTimeNs();
  if (c.info.latch != view::Latch::kNone) {
    Latched& slot = c.latched[c.info.latch == view::Latch::kLast ? 0 : key];
    slot = Latched{drawable, nullptr, t};
    c.pending = c.info.latch == view::Latch::kLast && c.live_wanted && !live;
  }
  if (!live && !c.full_wanted) {
    if (c.pending) cv_.notify_one();  // the worker delivers it once the rate allows
    return;
  }
  if (live && !c.full_wanted && c.info.latch == view::Latch::kNone && c.in_hub > 0) {
    // The channel's last message still waits for the worker: the newer one takes its place.
    auto waiting = std::find_if(inbox_.begin(), inbox_.end(),
                                [&](const Item& i) { return i.channel == id && i.live; });
    if (waiting != inbox_.end()) {
      waiting->drawable = std::move(drawable);
      waiting->log_time = t;
      ++dropped_;
      return;
    }
  }
  if (inbox_.size() >= options_.inbox_capacity) {
    // The worker is behind: the oldest stream message goes (latched ones are kept in the store
    // and their deliveries are rare).
    auto oldest = std::find_if(inbox_.begin(), inbox_.end(), [&](const Item& i) {
      return channels_[static_cast<size_t>(i.channel - 1)].info.latch == view::Latch::kNone;
    });
    if (oldest != inbox_.end()) {
      if (oldest->live) --channels_[static_cast<size_t>(oldest->channel - 1)].in_hub;
      inbox_.erase(oldest);
      ++dropped_;
    }
  }
  if (live) ++c.in_hub;
  inbox_.push_back(Item{id, key, t, std::move(drawable), live});
  lock.unlock();
  cv_.notify_one();
}

std::shared_ptr<const std::string> ViewHub::encode(const Channel& c,
                                                   const view::Drawable& d) const {
  try {
    if (const auto* grid = std::get_if<view::Grid>(&d); grid && grid->fill) {
      // A grid computed on demand: here, off the pipeline's thread.
      view::Grid filled = *grid;
      filled.fill = nullptr;
      grid->fill(filled);
      return std::make_shared<const std::string>(encodeJson(view::Drawable(std::move(filled))));
    }
    return std::make_shared<const std::string>(encodeJson(d));
  } catch (const std::exception& e) {
    spdlog::warn("viewer: cannot encode a message on {}: {}", c.info.topic, e.what());
    return nullptr;
  }
}

void ViewHub::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    // The nearest moment a rate-limited kLast message may go out.
    auto deadline = Clock::time_point::max();
    for (const Channel& c : channels_)
      if (c.pending) deadline = std::min(deadline, c.next_live);
    if (inbox_.empty() && !stop_) {
      if (deadline == Clock::time_point::max())
        cv_.wait(lock);
      else
        cv_.wait_until(lock, deadline);
    }
    if (stop_) return;
    std::vector<Item> batch(inbox_.begin(), inbox_.end());
    inbox_.clear();
    const auto now = Clock::now();
    for (Channel& c : channels_) {
      if (!c.pending || now < c.next_live) continue;
      c.pending = false;
      if (!c.live_wanted || c.latched.empty()) continue;
      c.next_live = now + c.live_period;
      ++c.in_hub;
      const Latched& l = c.latched.begin()->second;
      batch.push_back(Item{c.info.id, 0, l.log_time, l.drawable, true});
    }
    if (batch.empty()) continue;
    busy_ = true;
    lock.unlock();
    {
      std::lock_guard<std::mutex> deliver(deliver_mutex_);
      std::vector<ViewReceiver*> receivers;
      std::vector<ViewChannel> infos;
      {
        std::lock_guard<std::mutex> relock(mutex_);
        receivers = receivers_;
      }
      for (const Item& item : batch) {
        const Channel* c;
        {
          std::lock_guard<std::mutex> relock(mutex_);
          c = &channels_[static_cast<size_t>(item.channel - 1)];
        }
        auto payload = encode(*c, *item.drawable);
        if (!payload) {
          if (item.live) {
            std::lock_guard<std::mutex> relock(mutex_);
            --channels_[static_cast<size_t>(item.channel - 1)].in_hub;
          }
          continue;
        }
        ViewMessage m{item.channel, item.key, item.log_time, payload,
                      c->info.latch != view::Latch::kNone};
        if (m.latched) {
          std::lock_guard<std::mutex> relock(mutex_);
          auto& slots = channels_[static_cast<size_t>(item.channel - 1)].latched;
          auto it = slots.find(c->info.latch == view::Latch::kLast ? 0 : item.key);
          if (it != slots.end() && it->second.drawable == item.drawable) it->second.payload = payload;
        }
        for (ViewReceiver* r : receivers) {
          if (!r->wants(item.channel)) continue;
          if (!item.live && !r->fullRate()) continue;
          r->deliver(m);
        }
        if (item.live) {
          std::lock_guard<std::mutex> relock(mutex_);
          --channels_[static_cast<size_t>(item.channel - 1)].in_hub;
        }
      }
    }
    lock.lock();
    busy_ = false;
    idle_cv_.notify_all();
  }
}

void ViewHub::attach(ViewReceiver* receiver) {
  std::lock_guard<std::mutex> deliver(deliver_mutex_);
  std::vector<ViewChannel> infos;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    receivers_.push_back(receiver);
    for (const Channel& c : channels_) infos.push_back(c.info);
  }
  for (const auto& info : infos) receiver->channelAdded(info);
  interestChanged();
}

void ViewHub::detach(ViewReceiver* receiver) {
  std::lock_guard<std::mutex> deliver(deliver_mutex_);
  std::lock_guard<std::mutex> lock(mutex_);
  receivers_.erase(std::remove(receivers_.begin(), receivers_.end(), receiver), receivers_.end());
  refreshWants();
}

void ViewHub::interestChanged() {
  std::lock_guard<std::mutex> lock(mutex_);
  refreshWants();
}

void ViewHub::refreshWants() {
  for (Channel& c : channels_) {
    c.live_wanted = c.full_wanted = false;
    for (ViewReceiver* r : receivers_) {
      if (!r->wants(c.info.id)) continue;
      (r->fullRate() ? c.full_wanted : c.live_wanted) = true;
    }
  }
}

std::vector<ViewChannel> ViewHub::channels() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<ViewChannel> out;
  for (const Channel& c : channels_) out.push_back(c.info);
  return out;
}

std::vector<ViewMessage> ViewHub::latched(int id) {
  std::vector<std::pair<int64_t, Latched>> slots;
  const Channel* channel = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (id < 1 || id > static_cast<int>(channels_.size())) return {};
    channel = &channels_[static_cast<size_t>(id - 1)];
    slots.assign(channel->latched.begin(), channel->latched.end());
  }
  std::vector<ViewMessage> out;
  for (auto& [key, slot] : slots) {
    if (!slot.payload) {
      slot.payload = encode(*channel, *slot.drawable);
      if (!slot.payload) continue;
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = channels_[static_cast<size_t>(id - 1)].latched.find(key);
      if (it != channels_[static_cast<size_t>(id - 1)].latched.end() &&
          it->second.drawable == slot.drawable)
        it->second.payload = slot.payload;
    }
    out.push_back(ViewMessage{id, key, slot.log_time, slot.payload, true});
  }
  return out;
}

void ViewHub::clearLatched() {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Channel& c : channels_) {
    c.latched.clear();
    c.pending = false;
  }
}

void ViewHub::flush() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_cv_.wait(lock, [&] { return (inbox_.empty() && !busy_) || stop_; });
}

uint64_t ViewHub::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

}  // namespace plugslam::runtime
