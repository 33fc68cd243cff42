// A viewer connection's outgoing queue: the byte budget (starts empty, holds its rate over any
// window), latest-wins replacement per (channel, key), and the lanes' priorities. Time is driven
// by the test, so the bounds are exact.
#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "view/client_queue.h"

namespace plugslam::runtime {
namespace {

using Clock = ClientQueue::Clock;
using std::chrono::milliseconds;

ClientMessage message(int channel, size_t bytes, int64_t key = 0, char fill = 'x') {
  return ClientMessage{std::make_shared<const std::string>(bytes, fill), nullptr, true, channel,
                       key};
}

TEST(ClientQueueBudget, StartsEmpty) {
  const auto t0 = Clock::now();
  ByteBudget budget(1000.0, 50.0, t0);
  budget.advance(t0, 100);
  EXPECT_FALSE(budget.allows(1));  // nothing saved up at the start
  budget.advance(t0 + milliseconds(50), 100);
  EXPECT_TRUE(budget.allows(50));
  EXPECT_FALSE(budget.allows(51));
  EXPECT_GT(budget.when(100, t0 + milliseconds(50)), t0 + milliseconds(99));
  EXPECT_LE(budget.when(100, t0 + milliseconds(50)), t0 + milliseconds(101));
}

TEST(ClientQueueBudget, IdleTimeSavesAtMostTheBurst) {
  const auto t0 = Clock::now();
  ByteBudget budget(1000.0, 50.0, t0);
  budget.advance(t0 + std::chrono::seconds(10), 0);  // ten idle seconds
  EXPECT_TRUE(budget.allows(50));
  EXPECT_FALSE(budget.allows(51));
  // A message larger than the burst saves up for itself while it waits.
  budget.advance(t0 + std::chrono::seconds(11), 2000);
  EXPECT_TRUE(budget.allows(1050));
  EXPECT_FALSE(budget.allows(1051));
}

TEST(ClientQueue, TheBudgetStartsEmptyAndHoldsItsRateOverEveryWindow) {
  const double rate = 100000;  // bytes per second
  const double burst = 5000;
  const auto t0 = Clock::now();
  ClientQueue queue(rate, burst, t0);
  // Far more waiting than the budget passes: 200 messages of 3 kB on 200 channels at once.
  for (int c = 1; c <= 200; ++c) queue.push(message(c, 3000), ClientQueue::Lane::kBulk, t0);
  EXPECT_FALSE(queue.pop(t0).has_value());  // empty at the start: nothing leaves at once
  // Drain it by polling every millisecond, and record when each byte left.
  std::vector<std::pair<double, size_t>> sent;  // (seconds since t0, bytes)
  for (int ms = 0; ms <= 10000 && !queue.empty(); ++ms) {
    const auto now = t0 + milliseconds(ms);
    while (auto m = queue.pop(now)) sent.emplace_back(ms / 1000.0, m->size());
  }
  ASSERT_TRUE(queue.empty());
  ASSERT_EQ(sent.size(), 200u);
  // From the start, never more than the rate allows (600 kB at 100 kB/s: 6 s).
  size_t total = 0;
  for (const auto& [t, bytes] : sent) {
    total += bytes;
    EXPECT_LE(static_cast<double>(total), rate * t + 1e-6) << "at " << t << " s";
  }
  EXPECT_NEAR(sent.back().first, 6.0, 0.01);
  // Every window of every length: at most the rate over it plus what can be saved up at its
  // start (the burst, or the message waiting then when it is larger).
  for (size_t i = 0; i < sent.size(); ++i) {
    size_t bytes = 0;
    for (size_t j = i; j < sent.size(); ++j) {
      bytes += sent[j].second;
      const double window = sent[j].first - sent[i].first;
      EXPECT_LE(static_cast<double>(bytes), rate * window + burst + 1e-6);
    }
  }
}

TEST(ClientQueue, UrgentMessagesSkipTheBudgetButCountAgainstIt) {
  const auto t0 = Clock::now();
  ClientQueue queue(1000.0, 0.0, t0);
  queue.push(message(1, 500), ClientQueue::Lane::kBulk, t0);
  queue.push(message(2, 100), ClientQueue::Lane::kUrgent, t0);
  queue.pushControl(message(0, 10));
  // The reply first, then the urgent message, though the budget is empty.
  auto a = queue.pop(t0);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->channel, 0);
  auto b = queue.pop(t0);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->channel, 2);
  EXPECT_FALSE(queue.pop(t0));
  // The bulk message waits for 500 bytes plus the 110 borrowed: 0.61 s at 1000 B/s.
  EXPECT_FALSE(queue.pop(t0 + milliseconds(600)));
  const auto due = queue.nextDue(t0 + milliseconds(600));
  EXPECT_GT(due, t0 + milliseconds(609));
  EXPECT_LE(due, t0 + milliseconds(611));
  auto c = queue.pop(due);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->channel, 1);
  EXPECT_EQ(queue.nextDue(due), Clock::time_point::max());
}

TEST(ClientQueue, ANewerMessageReplacesTheWaitingOneInItsPlace) {
  const auto t0 = Clock::now();
  ClientQueue queue(0.0, 0.0, t0);  // no limit: order alone
  EXPECT_FALSE(queue.push(message(1, 10, 0, 'a'), ClientQueue::Lane::kBulk, t0));  // image
  EXPECT_FALSE(queue.push(message(2, 10, 7, 'b'), ClientQueue::Lane::kBulk, t0));  // map 7
  EXPECT_FALSE(queue.push(message(2, 10, 8, 'c'), ClientQueue::Lane::kBulk, t0));  // map 8
  // A newer image and a newer version of map 7 take the waiting ones' places.
  EXPECT_TRUE(queue.push(message(1, 20, 0, 'A'), ClientQueue::Lane::kBulk, t0));
  EXPECT_TRUE(queue.push(message(2, 30, 7, 'B'), ClientQueue::Lane::kBulk, t0));
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(queue.bytes(), 60u);
  EXPECT_TRUE(queue.holds(1));
  EXPECT_TRUE(queue.holds(2));
  EXPECT_FALSE(queue.holds(3));
  std::string order;
  while (auto m = queue.pop(t0)) order += m->head->front();
  EXPECT_EQ(order, "ABc");  // the newest of each, in the order they first arrived
  EXPECT_TRUE(queue.empty());
  EXPECT_EQ(queue.bytes(), 0u);
}

TEST(ClientQueue, AnUnsubscribedChannelLeavesTheQueue) {
  const auto t0 = Clock::now();
  ClientQueue queue(0.0, 0.0, t0);
  queue.push(message(1, 10, 0), ClientQueue::Lane::kBulk, t0);
  queue.push(message(2, 10, 0), ClientQueue::Lane::kBulk, t0);
  queue.push(message(2, 10, 1), ClientQueue::Lane::kBulk, t0);
  queue.push(message(2, 10, 2), ClientQueue::Lane::kUrgent, t0);
  EXPECT_EQ(queue.removeChannel(2), 3u);
  EXPECT_FALSE(queue.holds(2));
  EXPECT_EQ(queue.size(), 1u);
  EXPECT_EQ(queue.bytes(), 10u);
  auto m = queue.pop(t0);
  ASSERT_TRUE(m);
  EXPECT_EQ(m->channel, 1);
}

}  // namespace
}  // namespace plugslam::runtime
