#include "view/client_queue.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace plugslam::runtime {

ByteBudget::ByteBudget(double rate, double burst, Clock::time_point start)
    : rate_(rate), burst_(std::max(0.0, burst)), last_(start) {}

void ByteBudget::advance(Clock::time_point now, size_t waiting) {
  if (!limited() || now <= last_) return;
  const double dt = std::chrono::duration<double>(now - last_).count();
  last_ = now;
  // Never above the cap: time the lane spent idle is not a credit for a burst later.
  tokens_ = std::min(tokens_ + rate_ * dt, std::max(burst_, static_cast<double>(waiting)));
}

void ByteBudget::spend(size_t bytes) {
  if (limited()) tokens_ -= static_cast<double>(bytes);
}

ByteBudget::Clock::time_point ByteBudget::when(size_t bytes, Clock::time_point now) const {
  if (allows(bytes)) return now;
  const double seconds = (static_cast<double>(bytes) - tokens_) / rate_;
  // Rounded up to a whole microsecond, so that waking then finds the bytes there.
  return now + std::chrono::microseconds(static_cast<int64_t>(std::ceil(seconds * 1e6)) + 1);
}

ClientQueue::ClientQueue(double budget, double burst, Clock::time_point start)
    : budget_(budget, burst, start) {}

void ClientQueue::pushControl(ClientMessage message) {
  bytes_ += message.size();
  control_.push_back(std::move(message));
}

bool ClientQueue::push(ClientMessage message, Lane lane, Clock::time_point now) {
  advance(now);  // saved up so far, at the cap of what waited (an idle lane: the burst)
  Slots& slots = lane == Lane::kUrgent ? urgent_ : bulk_;
  const auto key = std::make_pair(message.channel, message.key);
  if (auto it = slots.index.find(key); it != slots.index.end()) {
    bytes_ = bytes_ - it->second->size() + message.size();
    *it->second = std::move(message);
    return true;
  }
  bytes_ += message.size();
  slots.order.push_back(std::move(message));
  slots.index[key] = std::prev(slots.order.end());
  return false;
}

ClientMessage ClientQueue::take(Slots& slots) {
  ClientMessage m = std::move(slots.order.front());
  slots.index.erase({m.channel, m.key});
  slots.order.pop_front();
  bytes_ -= m.size();
  return m;
}

void ClientQueue::advance(Clock::time_point now) {
  budget_.advance(now, bulk_.order.empty() ? 0 : bulk_.order.front().size());
}

std::optional<ClientMessage> ClientQueue::pop(Clock::time_point now) {
  advance(now);
  if (!control_.empty()) {
    ClientMessage m = std::move(control_.front());
    control_.pop_front();
    bytes_ -= m.size();
    budget_.spend(m.size());
    return m;
  }
  if (!urgent_.order.empty()) {
    budget_.spend(urgent_.order.front().size());
    return take(urgent_);
  }
  if (!bulk_.order.empty() && budget_.allows(bulk_.order.front().size())) {
    budget_.spend(bulk_.order.front().size());
    return take(bulk_);
  }
  return std::nullopt;
}

ClientQueue::Clock::time_point ClientQueue::nextDue(Clock::time_point now) {
  if (!control_.empty() || !urgent_.order.empty()) return now;
  if (bulk_.order.empty()) return Clock::time_point::max();
  advance(now);
  return budget_.when(bulk_.order.front().size(), now);
}

bool ClientQueue::holds(int channel) const {
  auto in = [channel](const Slots& s) {
    auto it = s.index.lower_bound({channel, std::numeric_limits<int64_t>::min()});
    return it != s.index.end() && it->first.first == channel;
  };
  return in(urgent_) || in(bulk_);
}

size_t ClientQueue::removeChannel(int channel) {
  size_t removed = 0;
  for (Slots* s : {&urgent_, &bulk_}) {
    for (auto it = s->index.lower_bound({channel, std::numeric_limits<int64_t>::min()});
         it != s->index.end() && it->first.first == channel;) {
      bytes_ -= it->second->size();
      s->order.erase(it->second);
      it = s->index.erase(it);
      ++removed;
    }
  }
  return removed;
}

size_t ClientQueue::size() const {
  return control_.size() + urgent_.order.size() + bulk_.order.size();
}

}  // namespace plugslam::runtime
