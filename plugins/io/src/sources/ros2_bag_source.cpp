#include "sources/ros2_bag_source.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <deque>
#include <map>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace io {

namespace {

// tf frame names with and without ROS 1's leading slash are one frame.
std::string frameName(const std::string& f) { return !f.empty() && f[0] == '/' ? f.substr(1) : f; }

bool endsWithDb3(const std::string& f) {
  return f.size() >= 4 && f.compare(f.size() - 4, 4, ".db3") == 0;
}

template <typename Msg>
void decode(const Ros2Message& m, Msg& out) {
  if (m.encoding != "cdr") {
    throw ParseError(m.file, 0, "topic " + m.topic + ", message at byte offset " +
                                    std::to_string(m.offset) + ": encoding '" + m.encoding +
                                    "' (only cdr is read)");
  }
  try {
    decodeCdr(reinterpret_cast<const std::uint8_t*>(m.data.data()), m.data.size(), out);
  } catch (const ParseError& e) {
    throw ParseError(m.file, 0, "topic " + m.topic + " (" + m.type + "), message at " +
                                    (endsWithDb3(m.file) ? "row " : "byte offset ") +
                                    std::to_string(m.offset) + ": " + e.message());
  }
}

}  // namespace

Ros2BagSource::Ros2BagSource()
    : BagSource("ROS 2 bag: a rosbag2 folder (metadata.yaml + .mcap or .db3 files), or one "
                ".mcap or .db3 file",
                "x, y, theta (m, m, rad) per scan topic; empty = from the bag's /tf_static") {}
Ros2BagSource::~Ros2BagSource() = default;

std::string Ros2BagSource::bagName() const { return "ROS 2 bag '" + path() + "'"; }

std::vector<BagTopic> Ros2BagSource::bagTopics() const {
  if (bag_) return bag_->topics();
  return Ros2Bag(path()).topics();
}

void Ros2BagSource::checkTopics() {
  // A mapped topic of another type would fail on its first message with a CDR error: say it
  // plainly, once, before the run.
  std::map<std::string, std::string> types;
  for (const auto& t : bag_->topics()) types[t.topic] = t.type;
  for (const auto& topic : scanTopics()) {
    const auto it = types.find(topic);
    if (it != types.end() && !it->second.empty() && it->second != kRos2LaserScan) {
      throw InputError(bagName() + ": topic " + topic + " is " + it->second + ", not " +
                       kRos2LaserScan + " (the only type read on `scans` topics)");
    }
  }
  if (odometryTopic().empty()) return;
  const auto it = types.find(odometryTopic());
  if (it == types.end()) {
    spdlog::warn("{} has no odometry topic {}: frames carry no odometry", bagName(),
                 odometryTopic());
  } else if (!it->second.empty() && it->second != kRos2Odometry) {
    throw InputError(bagName() + ": topic " + odometryTopic() + " is " + it->second + ", not " +
                     kRos2Odometry + " (the only type read on the `odometry` topic)");
  }
}

void Ros2BagSource::openBag() {
  if (!bag_) {
    bag_ = std::make_unique<Ros2Bag>(path());
    checkTopics();
  }
  std::set<std::string> topics(scanTopics().begin(), scanTopics().end());
  if (!odometryTopic().empty()) topics.insert(odometryTopic());
  bag_->open(topics);
}

bool Ros2BagSource::readReading(BagReading& r) {
  Ros2Message m;
  while (bag_->next(m)) {
    r.record_time = 1e-9 * static_cast<double>(m.log_time);
    if (m.topic == odometryTopic()) {
      r.kind = BagReading::Kind::kOdometry;
      decode(m, r.odometry);
      return true;
    }
    for (size_t i = 0; i < scanTopics().size(); ++i) {
      if (m.topic != scanTopics()[i]) continue;
      r.kind = BagReading::Kind::kScan;
      r.scan_index = i;
      decode(m, r.scan);
      return true;
    }
  }
  return false;
}

std::string Ros2BagSource::odometryFrame() {
  if (odometryTopic().empty()) return "";
  // The pose of an Odometry message is that of its child frame: the robot.
  Ros2Bag bag(path());
  bag.open({odometryTopic()});
  Ros2Message m;
  if (!bag.next(m)) return "";
  OdometryMsg odom;
  decode(m, odom);
  return frameName(odom.child_frame_id);
}

Eigen::Isometry2d Ros2BagSource::defaultMount(std::size_t index, const std::string& frame_id) {
  const std::string& topic = scanTopics()[index];
  const std::string laser = frameName(frame_id);
  if (tf_static().empty()) return Eigen::Isometry2d::Identity();
  bool has_tf = false;
  for (const auto& t : bag_->topics()) has_tf = has_tf || t.topic == tf_static();
  if (!has_tf) {
    spdlog::warn("{}: no {} topic and no `mounts`: scan topic {} is mounted at the robot's origin",
                 bagName(), tf_static(), topic);
    return Eigen::Isometry2d::Identity();
  }
  // The static tree as undirected edges (a breadth-first search from the robot frame) and each
  // frame's parent.
  std::multimap<std::string, std::pair<std::string, Eigen::Isometry3d>> edges;
  std::map<std::string, std::string> parent_of;
  Ros2Bag bag(path());
  bag.open({tf_static()});
  Ros2Message m;
  while (bag.next(m)) {
    TfMsg tf;
    decode(m, tf);
    for (const auto& t : tf.transforms) {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() << t.translation[0], t.translation[1], t.translation[2];
      T.linear() = Eigen::Quaterniond(t.rotation[3], t.rotation[0], t.rotation[1], t.rotation[2])
                       .normalized()
                       .toRotationMatrix();
      const std::string parent = frameName(t.header.frame_id);
      const std::string child = frameName(t.child_frame_id);
      edges.emplace(parent, std::make_pair(child, T));
      edges.emplace(child, std::make_pair(parent, T.inverse()));
      parent_of[child] = parent;
    }
  }
  // The robot: `base_frame`, else the odometry's child frame when the static tree has it, else
  // the root of the static tree the scanner hangs from (static transforms describe the rigid
  // robot; its root is the body odometry moves).
  std::string robot = frameName(base_frame());
  if (robot.empty()) {
    robot = odometryFrame();
    if (robot.empty() || (!parent_of.count(robot) && !edges.count(robot))) {
      robot = laser;
      for (size_t hops = 0; parent_of.count(robot) && hops < parent_of.size(); ++hops) {
        robot = parent_of[robot];
      }
    }
  }
  std::map<std::string, Eigen::Isometry3d> pose{{robot, Eigen::Isometry3d::Identity()}};
  std::deque<std::string> todo{robot};
  while (!todo.empty() && !pose.count(laser)) {
    const std::string f = todo.front();
    todo.pop_front();
    for (auto [it, end] = edges.equal_range(f); it != end; ++it) {
      if (pose.count(it->second.first)) continue;
      pose[it->second.first] = pose[f] * it->second.second;
      todo.push_back(it->second.first);
    }
  }
  const auto found = pose.find(laser);
  if (found == pose.end()) {
    spdlog::warn("{}: {} links no frame '{}' (scan topic {}) to the robot frame '{}'; mounted at "
                 "the robot's origin (set `mounts` or `base_frame`)",
                 bagName(), tf_static(), laser, topic, robot);
    return Eigen::Isometry2d::Identity();
  }
  const Eigen::Isometry3d& T = found->second;
  // The scan plane is the sensor's x-y plane: its heading is where its x axis points.
  const Eigen::Vector3d x = T.linear().col(0);
  const double yaw = std::atan2(x.y(), x.x());
  const Eigen::Vector3d z = T.linear().col(2);
  if (z.z() < std::cos(0.05)) {
    spdlog::warn("{}: frame '{}' is tilted {:.1f} deg from the robot's plane; the scan is used "
                 "as if level",
                 bagName(), laser, std::acos(std::min(1.0, std::abs(z.z()))) * 180.0 / M_PI);
  }
  spdlog::info("{}: scan topic {} mounted from {}: {} -> {} = ({:.4f}, {:.4f}, {:.4f})",
               bagName(), topic, tf_static(), robot, laser, T.translation().x(),
               T.translation().y(), yaw);
  return se2(T.translation().x(), T.translation().y(), yaw);
}

}  // namespace io
}  // namespace plugslam
