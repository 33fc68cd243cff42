#include "sources/ros2_bag_source.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <deque>
#include <map>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"
#include "readers/ros_images.h"

namespace plugslam {
namespace io {

namespace {

bool endsWithDb3(const std::string& f) {
  return f.size() >= 4 && f.compare(f.size() - 4, 4, ".db3") == 0;
}

std::string where(const Ros2Message& m) {
  return "topic " + m.topic + " (" + m.type + "), message at " +
         (endsWithDb3(m.file) ? "row " : "byte offset ") + std::to_string(m.offset);
}

// [x y z rx ry rz] (rotation vector) as a pose; ParamError naming `param` unless 6 numbers.
Eigen::Isometry3d poseParam(const char* param, const std::vector<double>& p) {
  if (p.size() != 6)
    throw ParamError(param, "expected 6 numbers [x y z rx ry rz], got " + std::to_string(p.size()));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
  const Eigen::Vector3d r(p[3], p[4], p[5]);
  if (r.norm() > 0) T.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).matrix();
  return T;
}

Eigen::Matrix3d rowMajor3(const std::array<double, 9>& a) {
  Eigen::Matrix3d R;
  R << a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7], a[8];
  return R;
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
    throw ParseError(m.file, 0, where(m) + ": " + e.message());
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
  for (const BagStream& st : streams()) {
    if (st.kind == BagStream::Kind::kScan) continue;
    const auto it = types.find(st.topic);
    if (it == types.end() || it->second.empty()) continue;
    const bool ok = it->second == kRos2Image ||
                    (st.kind == BagStream::Kind::kImage && it->second == kRos2CompressedImage);
    if (!ok)
      throw InputError(bagName() + ": topic " + st.topic + " is " + it->second + ", not " +
                       kRos2Image +
                       (st.kind == BagStream::Kind::kImage
                            ? std::string(" or ") + kRos2CompressedImage + " (read on `images`)"
                            : std::string(" (read on `depth`)")));
  }
  for (const std::string& topic : camera_info()) {
    const auto it = types.find(topic);
    if (it == types.end())
      throw InputError(bagName() + " has no camera_info topic " + topic);
    if (!it->second.empty() && it->second != kRos2CameraInfo)
      throw InputError(bagName() + ": topic " + topic + " is " + it->second + ", not " +
                       kRos2CameraInfo + " (read on `camera_info`)");
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
  std::set<std::string> topics;
  for (const BagStream& st : streams()) topics.insert(st.topic);
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
    for (size_t i = 0; i < streams().size(); ++i) {
      const BagStream& st = streams()[i];
      if (m.topic != st.topic) continue;
      r.stream = i;
      if (st.kind == BagStream::Kind::kScan) {
        r.kind = BagReading::Kind::kScan;
        decode(m, r.scan);
        return true;
      }
      if (decodeImage(m, st, r)) return true;
      break;
    }
  }
  return false;
}

bool Ros2BagSource::decodeImage(const Ros2Message& m, const BagStream& st, BagReading& r) {
  // Which camera of the rig took it: the second image of a pair, or depth with a depth camera
  // of its own, is calibration_.second.
  std::size_t ordinal = 0;  // among the image streams
  for (const BagStream& other : streams()) {
    if (&other == &st) break;
    if (other.kind == BagStream::Kind::kImage) ++ordinal;
  }
  const bool second = calibration_.second && (st.kind == BagStream::Kind::kDepth
                                                  ? camera_info().size() > 1
                                                  : ordinal == 1);
  const int width = second ? calibration_.second->width : calibration_.width;
  const int height = second ? calibration_.second->height : calibration_.height;
  try {
    if (st.kind == BagStream::Kind::kDepth) {
      ImageMsg msg;
      decode(m, msg);
      r.kind = BagReading::Kind::kDepth;
      r.header = msg.header;
      try {
        r.depth = depthFromRos(msg);
      } catch (const ParseError& e) {
        throw ParseError(m.file, 0, where(m) + ": " + e.message());
      }
      if (r.depth.width != width || r.depth.height != height)
        throw InputError(m.file + ": " + where(m) + ": depth image is " +
                         std::to_string(r.depth.width) + "x" + std::to_string(r.depth.height) +
                         ", its camera's is " + std::to_string(width) + "x" +
                         std::to_string(height));
      return true;
    }
    r.kind = BagReading::Kind::kImage;
    try {
      if (m.type == kRos2CompressedImage) {
        CompressedImageMsg msg;
        decode(m, msg);
        r.header = msg.header;
        r.image = imageFromRos(msg);
      } else {
        ImageMsg msg;
        decode(m, msg);
        r.header = msg.header;
        r.image = imageFromRos(msg);
      }
    } catch (const ParseError& e) {
      if (e.file() == m.file) throw;
      throw ParseError(m.file, 0, where(m) + ": " + e.message());
    }
    if (r.image.width != width || r.image.height != height)
      throw InputError(m.file + ": " + where(m) + ": image is " + std::to_string(r.image.width) +
                       "x" + std::to_string(r.image.height) + ", its camera's is " +
                       std::to_string(width) + "x" + std::to_string(height));
    return true;
  } catch (const InputError& e) {
    if (on_error() != "skip") throw;
    constexpr std::size_t kMaxWarnings = 5;
    ++skipped_images_;
    if (skipped_images_ <= kMaxWarnings)
      spdlog::warn("{}; message skipped{}", e.what(),
                   skipped_images_ == kMaxWarnings ? " (further skips at -v)" : "");
    else
      spdlog::debug("{}; message skipped", e.what());
    return false;
  }
}

std::vector<BagStream> Ros2BagSource::imageStreams() const {
  std::vector<BagStream> out;
  for (const auto& s : images()) {
    auto [topic, entry] = splitTopicEntry("images", s);
    out.push_back({BagStream::Kind::kImage, topic, entry});
  }
  if (!depth().empty()) {
    auto [topic, entry] = splitTopicEntry("depth", depth());
    out.push_back({BagStream::Kind::kDepth, topic, entry});
  }
  return out;
}

void Ros2BagSource::configure() {
  calibration_ = CameraInfo{};
  has_camera_ = false;
  skipped_images_ = 0;
  skips_summarized_ = false;
  bag_.reset();  // `path` may have changed since the last configure()
  if (images().empty() && !depth().empty())
    throw ParamError("depth", "needs the colour topic in `images`");
  if (images().size() > 2)
    throw ParamError("images", "one camera or a stereo pair: at most 2 topics, got " +
                                   std::to_string(images().size()));
  if (images().size() == 2 && !depth().empty())
    throw ParamError("depth", "a stereo pair with a depth topic is not read (one rig at a time)");
  if (!images().empty()) {
    if (camera().empty()) throw ParamError("camera", "must name a raw entry (not empty)");
    if (camera_info().empty())
      throw ParamError("camera_info", "needed with `images`: the CameraInfo topic of each camera");
    if (camera_info().size() > 2)
      throw ParamError("camera_info", "at most 2 topics (the first camera, the other camera)");
    if (images().size() == 2 && camera_info().size() != 2)
      throw ParamError("camera_info", "a stereo pair needs the CameraInfo topic of each camera");
  }
  BagSource::configure();
  if (!images().empty()) {
    for (const BagStream& st : streams())
      if (st.entry == camera()) throw ParamError("camera", "raw entry '" + st.entry + "' is used twice");
    setCalibration();
    has_camera_ = true;
  }
}

bool Ros2BagSource::next(Frame& frame) {
  if (!BagSource::next(frame)) {
    if (skipped_images_ > 0 && !skips_summarized_)
      spdlog::warn("{}: skipped {} image message(s) that did not decode or fit the calibration",
                   bagName(), skipped_images_);
    skips_summarized_ = true;
    return false;
  }
  if (has_camera_) frame.raw.set<CameraInfo>(camera(), calibration_);
  return true;
}

std::vector<ProvidedEntry> Ros2BagSource::provides() const {
  std::vector<ProvidedEntry> out = BagSource::provides();
  if (!images().empty()) out.push_back({camera(), typeid(CameraInfo)});
  return out;
}

void Ros2BagSource::setCalibration() {
  // The first message of each camera_info topic: calibrations do not change within a bag.
  std::vector<CameraInfoMsg> infos(camera_info().size());
  std::vector<bool> seen(infos.size(), false);
  {
    Ros2Bag bag(path());
    bag.open(std::set<std::string>(camera_info().begin(), camera_info().end()));
    Ros2Message m;
    std::size_t found = 0;
    while (found < infos.size() && bag.next(m)) {
      for (std::size_t i = 0; i < infos.size(); ++i) {
        if (m.topic != camera_info()[i] || seen[i]) continue;
        decode(m, infos[i]);
        seen[i] = true;
        ++found;
      }
    }
    for (std::size_t i = 0; i < infos.size(); ++i)
      if (!seen[i]) throw InputError(bagName() + " has no message on camera_info topic " +
                                     camera_info()[i]);
  }
  bool rect = rectified() == "yes";
  if (rectified() == "auto") {
    rect = true;
    for (const auto& info : infos) rect = rect && isRectifiedCamera(info);
  }
  auto intrinsics = [&](std::size_t i) {
    try {
      return intrinsicsFromRos(infos[i], rect);
    } catch (const ParseError& e) {
      throw InputError(bagName() + ": camera_info topic " + camera_info()[i] + ": " + e.message());
    }
  };
  const bool stereo = images().size() == 2;
  calibration_.setIntrinsics(intrinsics(0));
  const std::string first_frame = tfFrameName(infos[0].header.frame_id);
  // Where the first camera sits on the robot. The rectified frame is rotated by R from the raw
  // camera's (x_rect = R x_raw).
  const Eigen::Matrix3d R1 = rowMajor3(infos[0].r);
  if (!camera_mount().empty()) {
    calibration_.mount = poseParam("camera_mount", camera_mount());
  } else {
    const std::string robot = robotFrame(first_frame);
    auto pose = tf_static().empty() ? std::nullopt : staticPose(robot, first_frame);
    if (pose) {
      calibration_.mount = *pose;
      if (rect && stereo) calibration_.mount.linear() = pose->linear() * R1.transpose();
      spdlog::info("{}: camera {} mounted from {}: {} -> {}", bagName(), first_frame,
                   tf_static(), robot, first_frame);
    } else {
      spdlog::warn("{}: no static transform links camera frame '{}' to a robot frame and no "
                   "`camera_mount`: the camera is the robot frame",
                   bagName(), first_frame);
    }
  }
  if (!stereo && depth().empty()) return;  // mono
  if (stereo) {
    const CameraInfoMsg& right = infos[1];
    calibration_.second = intrinsics(1);
    // ROS's stereo calibration: P = K' [I | t], the right P's t = (-baseline, 0, 0) (its fourth
    // column is -fx' * baseline). The baseline is the camera centres' offset, -K'^-1 P.col(3),
    // as io.KittiSource takes it from calib.txt.
    auto centre = [](const CameraInfoMsg& info) {
      Eigen::Matrix<double, 3, 4> P;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) P(r, c) = info.p[4 * r + c];
      const Eigen::Matrix3d K = P.leftCols<3>();
      return Eigen::Vector3d(-K.inverse() * P.col(3));
    };
    const double B = right.p[0] != 0 && infos[0].p[0] != 0
                         ? (centre(right) - centre(infos[0])).x()
                         : 0.0;
    if (rect) {
      if (!(B > 0))
        throw InputError(bagName() + ": camera_info topic " + camera_info()[1] +
                         ": P[3] = " + std::to_string(right.p[3]) +
                         " gives no positive baseline (rectified pair: P[3] = -fx * baseline)");
      calibration_.baseline = B;
      calibration_.second_pose = Eigen::Translation3d(B, 0.0, 0.0) * Eigen::Isometry3d::Identity();
      if (!second_pose().empty())
        spdlog::warn("{}: `second_pose` ignored: a rectified pair sits at its P's baseline",
                     bagName());
      return;
    }
    if (!second_pose().empty()) {
      calibration_.second_pose = poseParam("second_pose", second_pose());
    } else if (B > 0) {
      // Right raw -> right rectified (R2), + baseline along x, -> left raw (R1^T).
      const Eigen::Matrix3d R2 = rowMajor3(right.r);
      calibration_.second_pose.linear() = R1.transpose() * R2;
      calibration_.second_pose.translation() = R1.transpose() * Eigen::Vector3d(B, 0, 0);
    } else if (auto pose = staticPose(first_frame, tfFrameName(right.header.frame_id))) {
      calibration_.second_pose = *pose;
    } else {
      throw InputError(bagName() + ": the stereo pair's relative pose is unknown: " +
                       camera_info()[1] + " has no baseline in P and " + tf_static() +
                       " links no '" + tfFrameName(right.header.frame_id) + "' to '" + first_frame +
                       "' (set `second_pose`)");
    }
    return;
  }
  // RGB-D: a depth camera of its own, or depth registered to colour (the colour pinhole).
  if (infos.size() > 1) {
    calibration_.second = intrinsics(1);
    const std::string depth_frame = tfFrameName(infos[1].header.frame_id);
    if (!second_pose().empty()) {
      calibration_.second_pose = poseParam("second_pose", second_pose());
    } else if (depth_frame != first_frame) {
      if (auto pose = staticPose(first_frame, depth_frame))
        calibration_.second_pose = *pose;
      else
        spdlog::warn("{}: {} links no depth frame '{}' to colour frame '{}': taken as the same "
                     "(set `second_pose`)",
                     bagName(), tf_static(), depth_frame, first_frame);
    }
  } else {
    calibration_.second = calibration_.intrinsics();
    if (!second_pose().empty()) calibration_.second_pose = poseParam("second_pose", second_pose());
  }
}

std::string Ros2BagSource::odometryChildFrame() {
  if (odometryTopic().empty()) return "";
  // The pose of an Odometry message is that of its child frame: the robot.
  Ros2Bag bag(path());
  bag.open({odometryTopic()});
  Ros2Message m;
  if (!bag.next(m)) return "";
  OdometryMsg odom;
  decode(m, odom);
  return tfFrameName(odom.child_frame_id);
}

std::vector<BagTransform> Ros2BagSource::rigidTransforms() {
  std::vector<BagTransform> out;
  if (tf_static().empty()) return out;
  bool has_tf = false;
  for (const auto& t : bag_->topics()) has_tf = has_tf || t.topic == tf_static();
  if (!has_tf) return out;
  Ros2Bag bag(path());
  bag.open({tf_static()});
  Ros2Message m;
  while (bag.next(m)) {
    TfMsg tf;
    decode(m, tf);
    for (const auto& t : tf.transforms) {
      out.push_back(BagTransform{tfFrameName(t.header.frame_id), tfFrameName(t.child_frame_id),
                                 tfPose(t.translation.data(), t.rotation.data()), tf_static()});
    }
  }
  return out;
}

}  // namespace io
}  // namespace plugslam
