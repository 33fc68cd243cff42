#include "sources/bag_source.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <type_traits>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace io {
namespace {

// How far past a frame's stamp (on the message clock) the bag is read before a stream is given
// up on; covers messages of one stream arriving late relative to another.
constexpr double kRecordSlack = 1.0;

// A scanner whose z axis leans more than this from the robot's [rad] is warned about: its scan is
// used as if level, so points far away land off by the sine of the lean times their range.
constexpr double kMaxTilt = 0.05;

std::string describe(const Eigen::Isometry2d& m) {
  return "(" + fmt::format("{:.4f}, {:.4f}, {:.4f}", m.translation().x(), m.translation().y(),
                           angleOf(m.linear())) +
         ")";
}

}  // namespace

Eigen::Isometry3d tfPose(const double* translation, const double* rotation_xyzw) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() << translation[0], translation[1], translation[2];
  pose.linear() = Eigen::Quaterniond(rotation_xyzw[3], rotation_xyzw[0], rotation_xyzw[1],
                                     rotation_xyzw[2])
                      .normalized()
                      .toRotationMatrix();
  return pose;
}

std::string tfFrameName(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

std::pair<std::string, std::string> splitTopicEntry(const std::string& param,
                                                    const std::string& text) {
  const auto colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
    throw ParamError(param,
                     "expected \"topic:entry\" (e.g. \"/scan:front_laser\"), got \"" + text + "\"");
  }
  return {text.substr(0, colon), text.substr(colon + 1)};
}

BagSource::BagSource(const char* path_doc, const char* mounts_doc)
    : path(this, "path", "", "", path_doc),
      mounts(this, "mounts", std::vector<double>{}, "", mounts_doc) {}

BagSource::~BagSource() = default;

void BagSource::configure() {
  if (path().empty()) throw ParamError("path", "required: the ROS bag to read");
  const std::vector<BagStream> images = imageStreams();
  if (scans().empty() && images.empty())
    throw ParamError("scans", "needs at least one \"topic:entry\" (or an image topic)");
  scan_topics_.clear();
  scan_entries_.clear();
  streams_.clear();
  std::set<std::string> entries, topics;
  for (const auto& s : scans()) {
    auto [topic, entry] = splitTopicEntry("scans", s);
    if (!topics.insert(topic).second) throw ParamError("scans", "topic " + topic + " listed twice");
    if (!entries.insert(entry).second) throw ParamError("scans", "entry " + entry + " used twice");
    scan_topics_.push_back(topic);
    scan_entries_.push_back(entry);
    streams_.push_back({BagStream::Kind::kScan, topic, entry});
  }
  for (const auto& s : images) {
    if (!topics.insert(s.topic).second)
      throw ParamError("images", "topic " + s.topic + " mapped twice");
    if (!entries.insert(s.entry).second)
      throw ParamError("images", "entry " + s.entry + " used twice");
    streams_.push_back(s);
  }
  odom_topic_.clear();
  odom_entry_.clear();
  if (!odometry().empty()) {
    std::tie(odom_topic_, odom_entry_) = splitTopicEntry("odometry", odometry());
    if (topics.count(odom_topic_)) throw ParamError("odometry", "topic is also a scan topic");
    if (entries.count(odom_entry_)) throw ParamError("odometry", "entry is also a scan entry");
  }
  const auto& m = mounts();
  if (!m.empty() && m.size() != 3 * scan_topics_.size()) {
    throw ParamError("mounts", "expected 3 numbers (x, y, theta) per scan topic: " +
                                   std::to_string(3 * scan_topics_.size()) + ", got " +
                                   std::to_string(m.size()));
  }
  config_mounts_.assign(scan_topics_.size(), std::nullopt);
  for (size_t i = 0; !m.empty() && i < scan_topics_.size(); ++i) {
    config_mounts_[i] = se2(m[3 * i], m[3 * i + 1], m[3 * i + 2]);
  }
  scan_mounts_.assign(scan_topics_.size(), std::nullopt);
  static_loaded_ = false;  // `path` may have changed since the last configure()
  open();
}

void BagSource::open() {
  openBag();
  opened_ = true;
  finished_ = false;
  latest_stamp_ = -std::numeric_limits<double>::infinity();
  primary_.clear();
  secondary_.assign(streams_.size() > 1 ? streams_.size() - 1 : 0, {});
  odom_.clear();
  size_hint_.reset();
  frames_without_odometry_ = 0;
  frames_dropped_ = 0;
  frames_ = 0;
  summarized_ = false;
  replay_.restart(bagName());
}

void BagSource::rewind() {
  // Queued readings of the previous pass are all older than the replay: drop them. Frames
  // without odometry are counted across replays; the end-of-bag warnings were given once.
  // Every stream of the bag is shifted by the replay's one offset.
  openBag();
  finished_ = false;
  primary_.clear();
  for (auto& q : secondary_) q.clear();
  odom_.clear();
}

void BagSource::noFramesError() const {
  // A misspelt topic would otherwise make an empty run; say what the bag holds.
  std::string topics;
  for (const auto& info : bagTopics()) {
    topics += (topics.empty() ? "" : ", ") + info.topic + " (" + info.type + ", " +
              std::to_string(info.count) + ")";
  }
  throw InputError(bagName() + " has no " +
                   (frames_dropped_ > 0 ? "complete frame on " : "message on ") +
                   (streams_[0].kind == BagStream::Kind::kScan ? "scan" : "image") + " topic " +
                   streams_[0].topic +
                   (frames_dropped_ > 0
                        ? " (" + std::to_string(frames_dropped_) +
                              " messages had no partner on every image topic within "
                              "sync_tolerance)"
                        : "") +
                   "; its topics: " + (topics.empty() ? "none" : topics));
}

std::vector<ProvidedEntry> BagSource::provides() const {
  std::vector<ProvidedEntry> out;
  for (const BagStream& s : streams_) {
    if (s.kind == BagStream::Kind::kScan) out.push_back({s.entry, typeid(LaserScan)});
    if (s.kind == BagStream::Kind::kImage) out.push_back({s.entry, typeid(Image)});
    if (s.kind == BagStream::Kind::kDepth) out.push_back({s.entry, typeid(DepthImage)});
  }
  if (!odom_entry_.empty()) out.push_back({odom_entry_, typeid(Odometry2D)});
  return out;
}

int64_t BagSource::sizeHint() const {
  if (size_hint_) return *size_hint_;
  if (path().empty() || scan_topics_.empty()) return -1;
  try {
    size_hint_ = 0;
    for (const auto& info : bagTopics()) {
      if (info.topic == scan_topics_[0]) size_hint_ = static_cast<int64_t>(info.count);
    }
    *size_hint_ = Replay::total(*size_hint_, repeat());
  } catch (const Error&) {
    size_hint_ = -1;
  }
  return *size_hint_;
}

bool BagSource::readOne() {
  BagReading r;
  if (!readReading(r)) return false;
  // Record times may be offset from header stamps (another clock), so readiness is judged on
  // the stamps actually used.
  auto stampOf = [&](const RosHeader& h) {
    double t = header_stamps() && h.stamp.toNsec() != 0 ? h.stamp.toSec() : r.record_time;
    t = replay_.shift(t);  // replays continue the clock
    latest_stamp_ = std::max(latest_stamp_, t);
    return t;
  };
  if (r.kind == BagReading::Kind::kOdometry) {
    const OdometryMsg& msg = r.odometry;
    Pose p{stampOf(msg.header), se2(msg.position[0], msg.position[1], msg.yaw())};
    // Kept sorted by stamp for the interpolation; out-of-order arrivals are rare and near the end.
    auto it = odom_.end();
    while (it != odom_.begin() && (it - 1)->t > p.t) --it;
    odom_.insert(it, p);
    return true;
  }
  const size_t i = r.stream;
  Stamped s;
  if (r.kind == BagReading::Kind::kImage) {
    s.t = stampOf(r.header);
    r.image.stamp = s.t;
    s.value = std::move(r.image);
  } else if (r.kind == BagReading::Kind::kDepth) {
    s.t = stampOf(r.header);
    r.depth.stamp = s.t;
    s.value = std::move(r.depth);
  } else {
    LaserScanMsg& msg = r.scan;
    if (!scan_mounts_[i]) scan_mounts_[i] = resolveMount(i, msg.header.frame_id);
    LaserScan scan;
    s.t = stampOf(msg.header);
    scan.stamp = s.t;
    scan.angle_min = msg.angle_min;
    scan.angle_increment = msg.angle_increment;
    scan.range_min = msg.range_min;
    scan.range_max = msg.range_max;
    scan.ranges = std::move(msg.ranges);
    scan.mount = *scan_mounts_[i];
    s.value = std::move(scan);
  }
  (i == 0 ? primary_ : secondary_[i - 1]).push_back(std::move(s));
  return true;
}

bool BagSource::ready(double t) const {
  if (finished_) return true;
  if (!odom_topic_.empty()) {
    const bool after = !odom_.empty() && odom_.back().t >= t;
    if (!after && latest_stamp_ <= t + max_odometry_gap() + kRecordSlack) return false;
  }
  for (const auto& q : secondary_) {
    const bool after = !q.empty() && q.back().t > t + sync_tolerance();
    if (!after && latest_stamp_ <= t + sync_tolerance() + kRecordSlack) return false;
  }
  return true;
}

std::optional<BagSource::Pose> BagSource::odometryAt(double t) const {
  if (odom_.empty()) return std::nullopt;
  auto it = std::lower_bound(odom_.begin(), odom_.end(), t,
                             [](const Pose& p, double v) { return p.t < v; });
  if (it != odom_.end() && it != odom_.begin()) {
    const Pose& a = *(it - 1);
    const Pose& b = *it;
    if (b.t - a.t <= max_odometry_gap()) {
      const double alpha = b.t > a.t ? (t - a.t) / (b.t - a.t) : 0.0;
      const Eigen::Vector3d d = toVector(a.pose.inverse() * b.pose);
      return Pose{t, a.pose * se2(alpha * d)};
    }
  }
  // Before the first, after the last, or across a gap: the nearest reading if close enough.
  const Pose* best = nullptr;
  if (it != odom_.end()) best = &*it;
  if (it != odom_.begin() && (!best || t - (it - 1)->t < best->t - t)) best = &*(it - 1);
  if (best && std::abs(best->t - t) <= max_odometry_gap()) return *best;
  return std::nullopt;
}

namespace {

void setEntry(PropertyContainer& raw, const std::string& entry,
              std::variant<LaserScan, Image, DepthImage>&& value) {
  std::visit([&](auto&& v) { raw.set<std::decay_t<decltype(v)>>(entry, std::move(v)); },
             std::move(value));
}

}  // namespace

bool BagSource::next(Frame& frame) {
  if (!opened_) open();
  for (;;) {
    if (!primary_.empty() && ready(primary_.front().t)) {
      if (emit(frame)) return true;
      continue;
    }
    if (finished_) {
      if (frames_ == 0) noFramesError();
      if (!summarized_) {
        if (frames_dropped_ > 0) {
          spdlog::warn("{}: dropped {} frame(s) of {} whose image topics had no message within "
                       "sync_tolerance {} s",
                       bagName(), frames_dropped_, streams_[0].topic, sync_tolerance());
        }
        endOfPass();
      }
      summarized_ = true;
      // A pass of fewer than two frames is spaced like a 10 Hz scanner.
      if (!replay_.next(repeat(), 0.1)) return false;
      rewind();
      continue;
    }
    if (!readOne()) finished_ = true;
  }
}

bool BagSource::emit(Frame& frame) {
  Stamped s = std::move(primary_.front());
  primary_.pop_front();
  const double t = s.t;
  // The partners first: a frame missing an image stream is dropped before it counts.
  std::vector<std::deque<Stamped>::iterator> match(secondary_.size());
  bool complete = true;
  for (size_t i = 0; i < secondary_.size(); ++i) {
    auto& q = secondary_[i];
    auto best = q.end();
    for (auto it = q.begin(); it != q.end(); ++it) {
      if (std::abs(it->t - t) <= sync_tolerance() &&
          (best == q.end() || std::abs(it->t - t) < std::abs(best->t - t))) {
        best = it;
      }
    }
    match[i] = best;
    if (best == q.end() && streams_[i + 1].kind != BagStream::Kind::kScan) complete = false;
  }
  if (!complete) {
    ++frames_dropped_;
    spdlog::debug("{}: frame at {:.6f} s dropped: an image topic has no message within {} s",
                  bagName(), t, sync_tolerance());
  } else {
    ++frames_;
    replay_.anchor(t);
    replay_.frame(t);
    frame.stamp = t;
    setEntry(frame.raw, streams_[0].entry, std::move(s.value));
    if (!odom_topic_.empty()) {
      if (auto odom = odometryAt(t)) {
        frame.raw.set<Odometry2D>(odom_entry_, {odom->t, odom->pose});
      } else {
        ++frames_without_odometry_;
      }
    }
  }
  if (!odom_topic_.empty()) {
    // Keep one reading at or before the next frame's time for its interpolation.
    const double keep = primary_.empty() ? t : std::min(t, primary_.front().t);
    while (odom_.size() > 1 && odom_[1].t <= keep) odom_.pop_front();
  }
  for (size_t i = 0; i < secondary_.size(); ++i) {
    auto& q = secondary_[i];
    if (complete && match[i] != q.end()) {
      setEntry(frame.raw, streams_[i + 1].entry, std::move(match[i]->value));
      q.erase(q.begin(), match[i] + 1);  // each secondary reading is used at most once
    }
    const double keep = primary_.empty() ? t : primary_.front().t;
    while (!q.empty() && q.front().t < keep - sync_tolerance()) q.pop_front();
  }
  return complete;
}

void BagSource::loadStatic() {
  if (static_loaded_) return;
  static_loaded_ = true;
  static_edges_.clear();
  static_parent_.clear();
  for (const BagTransform& t : rigidTransforms()) {
    static_edges_.emplace(t.parent, t);
    static_edges_.emplace(t.child, BagTransform{t.child, t.parent, t.pose.inverse(), t.topic});
    static_parent_[t.child] = t.parent;
  }
}

std::string BagSource::robotFrame(const std::string& sensor) {
  loadStatic();
  // The robot: `base_frame`, else the odometry's child frame when the static tree has it, else
  // the root of the static tree the sensor hangs from (static transforms describe the rigid
  // robot; its root is the body odometry moves).
  std::string robot = tfFrameName(base_frame());
  if (robot.empty()) {
    robot = tfFrameName(odometryChildFrame());
    if (robot.empty() || !static_edges_.count(robot)) {
      robot = sensor;
      for (size_t hops = 0; static_parent_.count(robot) && hops < static_parent_.size(); ++hops)
        robot = static_parent_[robot];
    }
  }
  return robot;
}

std::optional<Eigen::Isometry3d> BagSource::staticPose(const std::string& from,
                                                       const std::string& frame,
                                                       std::string* path) {
  loadStatic();
  // Breadth first from `from`; each frame reached keeps its pose and the edge it was reached by.
  std::map<std::string, Eigen::Isometry3d> pose{{from, Eigen::Isometry3d::Identity()}};
  std::map<std::string, const BagTransform*> via;
  std::deque<std::string> todo{from};
  while (!todo.empty() && !pose.count(frame)) {
    const std::string f = todo.front();
    todo.pop_front();
    for (auto [it, end] = static_edges_.equal_range(f); it != end; ++it) {
      if (pose.count(it->second.child)) continue;
      pose[it->second.child] = pose[f] * it->second.pose;
      via[it->second.child] = &it->second;
      todo.push_back(it->second.child);
    }
  }
  const auto found = pose.find(frame);
  if (found == pose.end()) return std::nullopt;
  if (path) {
    std::string text;
    for (std::string f = frame; via.count(f); f = via[f]->parent)
      text = " -> " + f + " (" + via[f]->topic + ")" + text;
    *path = from + text;
  }
  return found->second;
}

std::optional<Eigen::Isometry2d> BagSource::bagMount(const std::string& frame_id,
                                                     std::string& how, double& tilt) {
  const std::string laser = tfFrameName(frame_id);
  loadStatic();
  if (static_edges_.empty()) {
    how = transformTopics().empty()
              ? "no transform topic is read"
              : "the bag has no rigid transforms (" + transformTopics() + ")";
    return std::nullopt;
  }
  const std::string robot = robotFrame(laser);
  std::string path;
  // A scanner frame the tree does not hold is linked to nothing (not its own robot frame).
  const bool known = static_edges_.count(laser) > 0 || laser == robot;
  const auto found = known ? staticPose(robot, laser, &path) : std::nullopt;
  if (!found) {
    how = "the bag's rigid transforms (" + transformTopics() + ") link no frame '" + laser +
          "' to the robot frame '" + robot + "' (`base_frame` names another)";
    return std::nullopt;
  }
  const Eigen::Isometry3d& T = *found;
  // The scan plane is the sensor's x-y plane: its heading is where its x axis points.
  const Eigen::Vector3d x = T.linear().col(0);
  const Eigen::Vector3d z = T.linear().col(2);
  tilt = std::acos(std::min(1.0, std::abs(z.z())));
  if (z.z() < 0) tilt = M_PI - tilt;  // upside down: a mirrored scan
  how = path;
  return se2(T.translation().x(), T.translation().y(), std::atan2(x.y(), x.x()));
}

Eigen::Isometry2d BagSource::resolveMount(std::size_t i, const std::string& frame_id) {
  const std::string& topic = scan_topics_[i];
  std::string how;
  double tilt = 0;
  std::optional<Eigen::Isometry2d> from_bag;
  try {
    from_bag = bagMount(frame_id, how, tilt);
  } catch (const Error& e) {
    // With `mounts` the bag's transforms only check it: a bad transform topic does not stop a
    // run that does not need it.
    if (!config_mounts_[i]) throw;
    spdlog::warn("{}: scan topic {}: `mounts` not checked against the bag's transforms: {}",
                 bagName(), topic, e.what());
  }
  if (config_mounts_[i]) {
    const Eigen::Isometry2d& m = *config_mounts_[i];
    if (from_bag) {
      const Eigen::Isometry2d d = from_bag->inverse() * m;
      if (d.translation().norm() > kMountTolerance ||
          std::abs(angleOf(d.linear())) > kMountTolerance) {
        spdlog::warn("{}: scan topic {}: `mounts` {} is used; the bag's transforms say {} ({})",
                     bagName(), topic, describe(m), describe(*from_bag), how);
      } else {
        spdlog::debug("{}: scan topic {}: `mounts` {} agrees with the bag's transforms ({})",
                      bagName(), topic, describe(m), how);
      }
    }
    return m;
  }
  if (from_bag) {
    if (tilt > kMaxTilt) {
      spdlog::warn("{}: frame '{}' is tilted {:.1f} deg from the robot's plane; the scan is used "
                   "as if level",
                   bagName(), tfFrameName(frame_id), tilt * 180.0 / M_PI);
    }
    spdlog::info("{}: scan topic {} mounted at {} from the bag's transforms: {}", bagName(), topic,
                 describe(*from_bag), how);
    return *from_bag;
  }
  spdlog::warn("{}: no `mounts` and {}: scan topic {} is mounted at the robot's origin",
               bagName(), how, topic);
  return Eigen::Isometry2d::Identity();
}

}  // namespace io
}  // namespace plugslam
