#include "sources/rosbag_source.h"

#include <spdlog/spdlog.h>

#include "readers/ros_messages.h"

namespace plugslam {
namespace io {

RosbagSource::RosbagSource()
    : BagSource("ROS1 bag (v2.0) to read",
                "x, y, theta (m, m, rad) per scan topic; empty = identity") {}
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

}  // namespace io
}  // namespace plugslam
