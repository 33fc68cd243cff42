#include "sources/rosbag_source.h"

#include <spdlog/spdlog.h>

#include <array>
#include <map>
#include <set>
#include <utility>

#include "readers/ros_messages.h"

namespace plugslam {
namespace io {

RosbagSource::RosbagSource()
    : BagSource("ROS1 bag (v2.0) to read",
                "x, y, theta (m, m, rad) per scan topic; empty = from the bag's transforms "
                "(`tf_static`, the constant edges of `tf`)") {}
RosbagSource::~RosbagSource() = default;

void RosbagSource::openBag() {
  RosbagReaderOptions options;
  options.topics.insert(scanTopics().begin(), scanTopics().end());
  if (!odometryTopic().empty()) options.topics.insert(odometryTopic());
  reader_ = std::make_unique<RosbagReader>(path(), options);
}

bool RosbagSource::readReading(BagReading& r) {
  RosbagMessage message;
  // The reader returns only the mapped topics.
  while (reader_->next(message)) {
    const std::string& topic = message.connection->topic;
    r.record_time = message.time.toSec();
    if (topic == odometryTopic()) {
      r.kind = BagReading::Kind::kOdometry;
      decodeOdometry(*reader_, message, r.odometry);
      return true;
    }
    for (size_t i = 0; i < scanTopics().size(); ++i) {
      if (topic != scanTopics()[i]) continue;
      r.kind = BagReading::Kind::kScan;
      r.stream = i;
      decodeLaserScan(*reader_, message, r.scan);
      return true;
    }
  }
  return false;
}

std::vector<BagTopic> RosbagSource::bagTopics() const {
  std::vector<BagTopic> out;
  for (const auto& info : summarizeRosbag(path())) out.push_back({info.topic, info.type, info.count});
  return out;
}

std::string RosbagSource::bagName() const { return "ROS bag '" + path() + "'"; }

void RosbagSource::endOfPass() {
  if (reader_->stats().out_of_order > 0) {
    spdlog::warn(
        "ROS bag '{}': {} message(s) older than one already read (clock jump or "
        "unsorted chunks); returned in file order",
        path(), reader_->stats().out_of_order);
  }
}

std::string RosbagSource::transformTopics() const {
  if (tf_static().empty()) return tf().empty() ? "" : "the constant edges of " + tf();
  return tf().empty() ? tf_static() : tf_static() + " and the constant edges of " + tf();
}

std::string RosbagSource::odometryChildFrame() {
  if (odometryTopic().empty()) return "";
  // The pose of an Odometry message is that of its child frame: the robot.
  RosbagReaderOptions options;
  options.topics = {odometryTopic()};
  RosbagReader bag(path(), options);
  RosbagMessage m;
  if (!bag.next(m)) return "";
  OdometryMsg odom;
  decodeOdometry(bag, m, odom);
  return tfFrameName(odom.child_frame_id);
}

std::vector<BagTransform> RosbagSource::rigidTransforms() {
  std::vector<BagTransform> out;
  RosbagReaderOptions options;
  if (!tf_static().empty()) options.topics.insert(tf_static());
  if (!tf().empty()) options.topics.insert(tf());
  if (options.topics.empty()) return out;
  // Per edge (parent, child): its value, how often `tf` gave it and whether that ever changed. A
  // `tf_static` edge is rigid by declaration (its last value counts) and needs no repetition.
  struct Edge {
    std::array<double, 7> value{};
    std::string topic;
    std::size_t seen = 0;
    bool changed = false;
    bool declared_static = false;
  };
  std::map<std::pair<std::string, std::string>, Edge> edges;
  std::set<std::string> other_types;
  RosbagReader bag(path(), options);
  RosbagMessage m;
  while (bag.next(m)) {
    const RosbagConnection& c = *m.connection;
    if (c.type != kRosTfMessage.name && c.type != kTfMessageOldType) {
      if (other_types.insert(c.topic).second)
        spdlog::warn("{}: topic {} is {}, not {}: no transforms read from it", bagName(), c.topic,
                     c.type, kRosTfMessage.name);
      continue;
    }
    TfMsg msg;
    decodeTf(bag, m, msg);
    const bool declared_static = c.topic == tf_static();
    for (const TransformMsg& t : msg.transforms) {
      Edge& e = edges[{tfFrameName(t.header.frame_id), tfFrameName(t.child_frame_id)}];
      const std::array<double, 7> value{t.translation[0], t.translation[1], t.translation[2],
                                        t.rotation[0],    t.rotation[1],    t.rotation[2],
                                        t.rotation[3]};
      if (declared_static) {
        e.value = value;
        e.topic = c.topic;
        e.declared_static = true;
      } else if (!e.declared_static) {
        if (e.seen == 0) {
          e.value = value;
          e.topic = c.topic;
        } else if (value != e.value) {
          e.changed = true;
        }
        ++e.seen;
      }
    }
  }
  for (const auto& [frames, e] : edges) {
    if (!e.declared_static && (e.changed || e.seen < 2)) continue;
    out.push_back(BagTransform{
        frames.first, frames.second, tfPose(e.value.data(), e.value.data() + 3),
        e.declared_static ? e.topic
                          : e.topic + ", the same in its " + std::to_string(e.seen) + " messages"});
  }
  return out;
}

}  // namespace io
}  // namespace plugslam
