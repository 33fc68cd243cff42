// The viewer stream's hub: latching, rate limits, full-rate recordings, and that publishing never
// waits for a receiver. Also the drawables' JSON encoding and the drawer table. No test waits for
// time to pass: a stalled receiver is one held in deliver() until the test releases it, and a
// rate is either unlimited or so slow that no second message can be due during a test.
#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <limits>
#include <thread>

#include "plugslam/view/drawers.h"
#include "plugslam/view/publisher.h"
#include "view/view_hub.h"
#include "view/jpeg.h"
#include "view/view_json.h"

namespace plugslam::runtime {
namespace {

// No limit on a channel's rate: every message may go live as soon as the last one was taken.
constexpr double kUnlimited = std::numeric_limits<double>::infinity();
// One message per 1000 s: the first goes live, no second one is due while a test runs.
constexpr double kOnce = 1e-3;

// Records what the hub delivers. Held, it stalls in deliver() (on the hub's worker thread) until
// released; the test can wait until a delivery has begun.
class Recorder final : public ViewReceiver {
 public:
  explicit Recorder(bool full_rate = false) : full_rate_(full_rate) {}
  void channelAdded(const ViewChannel& c) override {
    std::lock_guard<std::mutex> lock(mutex_);
    channels.push_back(c);
  }
  void deliver(const ViewMessage& m) override {
    std::unique_lock<std::mutex> lock(mutex_);
    ++begun_;
    changed_.notify_all();
    changed_.wait(lock, [&] { return !held_; });
    messages.push_back(m);
  }
  bool wants(int) const override { return true; }
  bool fullRate() const override { return full_rate_; }
  bool ready(int) const override { return is_ready; }
  size_t count() {
    std::lock_guard<std::mutex> lock(mutex_);
    return messages.size();
  }
  void hold() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = true;
  }
  void release() {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = false;
    changed_.notify_all();
  }
  /// Returns once `n` deliveries have begun (the n-th may still be held).
  void waitForDeliveries(size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return begun_ >= n; });
  }
  std::vector<ViewChannel> channels;
  std::vector<ViewMessage> messages;
  std::atomic<bool> is_ready{true};  // false: as if its last message still waited to be sent

 private:
  bool full_rate_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool held_ = false;
  size_t begun_ = 0;
};

view::Status status(uint64_t frame) {
  view::Status s;
  s.frame = frame;
  s.state = "running";
  return s;
}

TEST(ViewChannel, WithoutAPublisherNothingHappens) {
  view::installPublisher(nullptr);
  view::Channel<view::Status> channel("/status", view::Latch::kLast);
  EXPECT_FALSE(channel.wanted());
  channel.publish(status(1));  // no publisher: dropped, no crash
}

TEST(ViewChannel, DeclaresWithTheInstalledPublisher) {
  ViewHub hub;
  view::installPublisher(&hub);
  view::Channel<view::Status> channel("/status", view::Latch::kLast);
  EXPECT_TRUE(channel.wanted());  // latched: kept for later receivers
  channel.publish(status(3));
  view::installPublisher(nullptr);
  ASSERT_EQ(hub.channels().size(), 1u);
  EXPECT_EQ(hub.channels()[0].topic, "/status");
  EXPECT_EQ(hub.channels()[0].schema_name, "plugslam.Status");
  const auto latched = hub.latched(hub.channels()[0].id);
  ASSERT_EQ(latched.size(), 1u);
  EXPECT_NE(latched[0].payload->find("\"frame\":3"), std::string::npos);
}

TEST(ViewHub, TheSameTopicWithAnotherKindIsRefused) {
  ViewHub hub;
  const int id = hub.declare("/a", view::kindOf<view::Status>(), view::Latch::kLast);
  EXPECT_EQ(hub.declare("/a", view::kindOf<view::Status>(), view::Latch::kLast), id);
  EXPECT_THROW(hub.declare("/a", view::kindOf<view::Grid>(), view::Latch::kLast), InputError);
}

TEST(ViewHub, LatchedLastAndPerKeyKeepTheNewest) {
  ViewHub hub;
  const int last = hub.declare("/last", view::kindOf<view::Status>(), view::Latch::kLast);
  const int keyed = hub.declare("/keyed", view::kindOf<view::Status>(), view::Latch::kPerKey);
  for (uint64_t i = 1; i <= 3; ++i) hub.publish(last, status(i), 0);
  hub.publish(keyed, status(10), 0);
  hub.publish(keyed, status(11), 1);
  hub.publish(keyed, status(12), 0);
  const auto l = hub.latched(last);
  ASSERT_EQ(l.size(), 1u);
  EXPECT_NE(l[0].payload->find("\"frame\":3"), std::string::npos);
  const auto k = hub.latched(keyed);
  ASSERT_EQ(k.size(), 2u);
  EXPECT_NE(k[0].payload->find("\"frame\":12"), std::string::npos);
  EXPECT_NE(k[1].payload->find("\"frame\":11"), std::string::npos);
  hub.clearLatched();
  EXPECT_TRUE(hub.latched(keyed).empty());
}

TEST(ViewHub, LiveStreamsAreRateLimitedRecordingsAreNot) {
  ViewHubOptions options;
  options.stream_rate = kOnce;
  ViewHub hub(options);
  Recorder live, recording(/*full_rate=*/true);
  hub.attach(&live);
  hub.attach(&recording);
  // Declared after the receivers attached: the recording must still get it from the start.
  const int id = hub.declare("/pose", view::kindOf<view::PoseInFrame>(), view::Latch::kNone);
  ASSERT_TRUE(hub.wants(id));
  for (int i = 0; i < 50; ++i) hub.publish(id, view::PoseInFrame{}, 0);
  hub.flush();
  EXPECT_EQ(recording.count(), 50u);
  EXPECT_EQ(live.count(), 1u);
  hub.detach(&live);
  hub.detach(&recording);
}

TEST(ViewHub, AStalledReceiverNeverBlocksThePublisher) {
  ViewHubOptions options;
  options.inbox_capacity = 64;
  ViewHub hub(options);
  Recorder stalled(/*full_rate=*/true);
  stalled.hold();  // takes nothing until released below
  hub.attach(&stalled);
  const int id = hub.declare("/scan", view::kindOf<view::PoseInFrame>(), view::Latch::kNone);
  // A publisher that waited for the receiver would never get past this loop (the suite's
  // timeout would report the hang).
  for (int i = 0; i < 2000; ++i) hub.publish(id, view::PoseInFrame{}, 0);
  EXPECT_EQ(stalled.count(), 0u);
  EXPECT_GT(hub.dropped(), 1000u);  // the inbox kept at most 64 + one batch in flight
  stalled.release();
  hub.flush();
  EXPECT_EQ(stalled.count() + hub.dropped(), 2000u);  // each one delivered or counted dropped
  hub.detach(&stalled);
}

TEST(ViewHub, GridsAreFilledOffThePublishersThread) {
  ViewHub hub;
  Recorder recording(/*full_rate=*/true);
  hub.attach(&recording);
  const int id = hub.declare("/grid", view::kindOf<view::Grid>(), view::Latch::kPerKey);
  std::atomic<bool> same_thread{true};
  const auto publisher = std::this_thread::get_id();
  view::Grid grid;
  grid.fill = [&](view::Grid& g) {
    same_thread = std::this_thread::get_id() == publisher;
    g.width = 2;
    g.height = 1;
    g.cells = {0, 100};
  };
  hub.publish(id, std::move(grid), 7);
  hub.flush();
  ASSERT_EQ(recording.count(), 1u);
  EXPECT_FALSE(same_thread.load());
  EXPECT_NE(recording.messages[0].payload->find("\"column_count\":2"), std::string::npos);
  EXPECT_EQ(recording.messages[0].key, 7);
  hub.detach(&recording);
}

TEST(ViewHub, AStreamMessageIsBuiltOnlyForAReceiverThatTookTheLastOne) {
  ViewHubOptions options;
  options.stream_rate = kUnlimited;  // the rate is not what holds it back here
  ViewHub hub(options);
  Recorder live;
  hub.attach(&live);
  const int id = hub.declare("/scan", view::kindOf<view::PointCloud>(), view::Latch::kNone);
  EXPECT_TRUE(hub.wants(id));
  live.is_ready = false;
  EXPECT_FALSE(hub.wants(id));
  hub.publish(id, view::PointCloud{}, 0);  // published anyway: nobody would take it live
  hub.flush();
  EXPECT_EQ(live.count(), 0u);
  live.is_ready = true;
  EXPECT_TRUE(hub.wants(id));
  hub.publish(id, view::PointCloud{}, 0);
  hub.flush();
  EXPECT_EQ(live.count(), 1u);
  hub.detach(&live);
}

TEST(ViewHub, ANewerStreamMessageReplacesOneStillInTheInbox) {
  ViewHubOptions options;
  options.stream_rate = kUnlimited;
  ViewHub hub(options);
  Recorder live;
  hub.attach(&live);
  const int id = hub.declare("/pose", view::kindOf<view::PoseInFrame>(), view::Latch::kNone);
  live.hold();
  hub.publish(id, view::PoseInFrame{1.0}, 0);
  live.waitForDeliveries(1);                   // the worker took it and is busy delivering it
  hub.publish(id, view::PoseInFrame{2.0}, 0);  // waits in the inbox
  hub.publish(id, view::PoseInFrame{3.0}, 0);  // takes its place
  live.release();
  hub.flush();
  ASSERT_EQ(live.count(), 2u);
  EXPECT_NE(live.messages[0].payload->find("\"sec\":1"), std::string::npos);
  EXPECT_NE(live.messages[1].payload->find("\"sec\":3"), std::string::npos);
  EXPECT_EQ(hub.dropped(), 1u);
  hub.detach(&live);
}

TEST(ViewHub, CameraImagesGoLiveAtTheImageRate) {
  ViewHubOptions options;
  options.stream_rate = kUnlimited;
  options.image_rate = kOnce;
  ViewHub hub(options);
  Recorder live;
  hub.attach(&live);
  const int image = hub.declare("/camera/left/image", view::kindOf<view::CameraImage>(),
                                view::Latch::kNone);
  const int scan = hub.declare("/scan", view::kindOf<view::PointCloud>(), view::Latch::kNone);
  view::CameraImage m{"camera/left", {}};
  m.image.resize(8, 4, 1);
  ASSERT_TRUE(hub.wants(image));
  hub.publish(image, view::CameraImage(m), 0);
  hub.publish(scan, view::PointCloud{}, 0);
  hub.flush();
  EXPECT_FALSE(hub.wants(image));  // the next image is due 1000 s after this one
  EXPECT_TRUE(hub.wants(scan));    // other channels: at once
  EXPECT_EQ(live.count(), 2u);
  hub.detach(&live);
}

TEST(ViewImage, ShrinksWhileCopyingAsTheEncoderWould) {
  // KITTI's width: shrunk by 2, each pixel the rounded mean of its 2x2 block.
  Image grey;
  grey.resize(1241, 5, 1);
  for (int y = 0; y < 5; ++y)
    for (int x = 0; x < 1241; ++x) grey.data[y * 1241 + x] = static_cast<uint8_t>((x * 7 + y * 13) % 256);
  const Image small = viewImage(grey);
  ASSERT_EQ(small.width, 620);
  ASSERT_EQ(small.height, 2);
  EXPECT_EQ(small.stride, 620);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 620; ++x) {
      const int sum = grey.at(2 * x, 2 * y) + grey.at(2 * x + 1, 2 * y) + grey.at(2 * x, 2 * y + 1) +
                      grey.at(2 * x + 1, 2 * y + 1);
      ASSERT_EQ(small.at(x, y), (sum + 2) / 4) << x << "," << y;
    }
  // RGB with a padded stride, and a factor of 3 (1920 px).
  Image rgb;
  rgb.width = 1920;
  rgb.height = 3;
  rgb.channels = 3;
  rgb.stride = 1920 * 3 + 16;
  rgb.data.assign(static_cast<size_t>(rgb.stride) * 3, 0);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 1920; ++x) rgb.data[y * rgb.stride + x * 3 + 1] = static_cast<uint8_t>(x % 3 == 0 ? 90 : 0);
  const Image shrunk = viewImage(rgb);
  ASSERT_EQ(shrunk.width, 640);
  ASSERT_EQ(shrunk.height, 1);
  EXPECT_EQ(shrunk.at(5, 0, 0), 0);
  EXPECT_EQ(shrunk.at(5, 0, 1), 30);  // one pixel of 90 in each 3x3 block's columns: 270 / 9
  EXPECT_EQ(viewCalibration([] {
              CameraInfo c;
              c.width = 1920;
              c.height = 3;
              return c;
            }()).width,
            shrunk.width);
  // Already small: as it is, and the encoder compresses it without shrinking again.
  const Image same = viewImage(shrunk);
  EXPECT_EQ(same.width, 640);
  EXPECT_FALSE(encodeJpeg(same).empty());
}

TEST(ViewJson, Base64MatchesRfc4648) {
  EXPECT_EQ(base64("", 0), "");
  EXPECT_EQ(base64("f", 1), "Zg==");
  EXPECT_EQ(base64("fo", 2), "Zm8=");
  EXPECT_EQ(base64("foo", 3), "Zm9v");
  EXPECT_EQ(base64("foobar", 6), "Zm9vYmFy");
}

TEST(ViewJson, PointCloudsPackFloatsAndColours) {
  view::PointCloud c;
  c.stamp = 1.5;
  c.frame = "map/3";
  c.points = {{1, 2, 3}, {4, 5, 6}};
  const std::string plain = encodeJson(c);
  EXPECT_NE(plain.find("\"point_stride\":12"), std::string::npos);
  EXPECT_NE(plain.find("\"timestamp\":{\"nsec\":500000000,\"sec\":1}"), std::string::npos);
  EXPECT_NE(plain.find("\"data\":\"" + base64(c.points.data(), 24) + "\""), std::string::npos);
  c.colors = {{{255, 0, 0, 255}}, {{0, 255, 0, 255}}};
  const std::string colored = encodeJson(c);
  EXPECT_NE(colored.find("\"point_stride\":16"), std::string::npos);
  EXPECT_NE(colored.find("\"red\""), std::string::npos);
}

TEST(ViewJson, EveryKindHasANameAndASchema) {
  for (size_t k = 0; k < std::variant_size_v<view::Drawable>; ++k) {
    EXPECT_FALSE(schemaName(k).empty()) << k;
    EXPECT_NE(jsonSchema(k).find("\"title\":\"" + schemaName(k) + "\""), std::string::npos) << k;
  }
}

TEST(ViewDrawers, DrawByTypeAndForgetAnOwner) {
  auto& drawers = view::Drawers::instance();
  drawers.add<double>("test_owner", [](const double& v, view::PointCloud& out) {
    out.points.emplace_back(static_cast<float>(v), 0.0f, 0.0f);
  });
  Property<double> p("x", 2.5);
  view::PointCloud cloud;
  ASSERT_TRUE(drawers.draw(p, cloud));
  ASSERT_EQ(cloud.points.size(), 1u);
  EXPECT_FLOAT_EQ(cloud.points[0].x(), 2.5f);
  EXPECT_EQ(drawers.removeOwner("test_owner"), 1u);
  EXPECT_FALSE(drawers.canDraw(typeid(double)));
  EXPECT_FALSE(drawers.draw(p, cloud));
}

}  // namespace
}  // namespace plugslam::runtime
