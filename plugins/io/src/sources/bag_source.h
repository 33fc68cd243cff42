#pragma once
// The part of the ROS bag sources that does not depend on the bag's format: the topic -> entry
// mapping, the synchronisation of scans and odometry into one frame per primary scan, the mounts
// (from the config or the bag's transform tree) and the replays. io.RosbagSource (ROS 1) and
// io.Ros2BagSource (rosbag2, MCAP) read messages and hand them over decoded.
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "readers/ros_messages.h"
#include "sources/replay.h"

namespace plugslam {
namespace io {

/// One topic of a bag, for messages and size hints.
struct BagTopic {
  std::string topic;      ///< topic name
  std::string type;       ///< message type as the bag names it
  std::size_t count = 0;  ///< messages on it
};

/// One synchronised stream of a bag: a scan topic, or an image topic a source adds (cameras).
struct BagStream {
  /// What its messages become in the frame.
  enum class Kind { kScan, kImage, kDepth };
  Kind kind = Kind::kScan;  ///< LaserScan, Image or DepthImage entries
  std::string topic;        ///< topic name
  std::string entry;        ///< raw entry name
};

/// One rigid transform of a bag: an edge of its transform tree that does not move.
struct BagTransform {
  std::string parent;  ///< parent frame, without ROS 1's leading slash
  std::string child;   ///< child frame, likewise
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the child frame in the parent's
  std::string topic;  ///< the topic it was read from, for messages
};

/// A tf frame name without ROS 1's leading slash: "/base_link" and "base_link" are one frame.
std::string tfFrameName(const std::string& frame);

/// A tf transform's pose: translation [m] and rotation quaternion x y z w, as both ROS encode it.
Eigen::Isometry3d tfPose(const double* translation, const double* rotation_xyzw);

/// One decoded message of a mapped topic.
struct BagReading {
  /// Which stream it belongs to.
  enum class Kind { kScan, kOdometry, kImage, kDepth };
  Kind kind = Kind::kScan;      ///< a scan or image stream, or the odometry topic
  std::size_t stream = 0;       ///< index of its stream (scan topics first; not kOdometry)
  double record_time = 0;       ///< receipt time [s], used without a header stamp
  LaserScanMsg scan;            ///< kScan
  OdometryMsg odometry;         ///< kOdometry
  RosHeader header;             ///< kImage, kDepth: the message's header
  Image image;                  ///< kImage, decoded
  DepthImage depth;             ///< kDepth, decoded [m]
};

/// One frame per message of the first stream (the first scan topic, else the source's first image
/// topic), stamped with its header time. The odometry is interpolated at that time between the
/// neighbouring odometry messages (when they are at most max_odometry_gap apart; else the nearest
/// within the gap, with that message's stamp; else none). Every other stream contributes its
/// message nearest in time within sync_tolerance; a frame that lacks an image stream's message is
/// dropped (a stereo pair or an RGB-D pair is useless in halves) and counted. A bag with no
/// message on the first stream is an InputError listing the bag's topics.
///
/// Each scan topic's mount is, when `mounts` is empty, the pose of its first message's frame in
/// the robot frame, composed along the bag's rigid transforms (rigidTransforms()); the mount used
/// is logged once. `mounts` wins when given, with a warning when the bag's transforms say
/// otherwise; without either the scanner is at the robot's origin, with a warning.
class BagSource : public Source {
 public:
  Param<std::string> path;
  Param<std::vector<std::string>> scans{this,
                                        "scans",
                                        {"/scan:front_laser"},
                                        "",
                                        "LaserScan topics as \"topic:entry\"; the first one "
                                        "paces the frames"};
  Param<std::string> odometry{this, "odometry", "/odom:odom", "",
                              "Odometry topic as \"topic:entry\"; empty = none"};
  Param<double> max_odometry_gap{this,
                                 "max_odometry_gap",
                                 0.5,
                                 "s",
                                 "longest gap between odometry messages to interpolate across",
                                 Range{0.0, 3600.0}};
  Param<double> sync_tolerance{this,
                               "sync_tolerance",
                               0.05,
                               "s",
                               "largest time offset of a secondary scan from the frame",
                               Range{0.0, 3600.0}};
  Param<std::vector<double>> mounts;
  Param<bool> header_stamps{this, "header_stamps", true, "",
                            "use message header stamps (false: bag record times)"};
  Param<int64_t> repeat{this,
                        "repeat",
                        1,
                        "",
                        "times to play the bag (0: endlessly, until max_frames or Ctrl-C); "
                        "stamps keep increasing across replays",
                        Range{0, 1e9}};
  Param<std::string> tf_static{this, "tf_static", "/tf_static", "",
                               "topic of the static transforms the mounts come from when "
                               "`mounts` is empty; empty = none"};
  Param<std::string> base_frame{this, "base_frame", "", "",
                                "robot frame of the mounts; empty = the odometry's "
                                "child_frame_id, else the root of the scanner's static tree"};

  /// A mount in `mounts` and the bag's differ by more than this (m, and rad) before it is said.
  static constexpr double kMountTolerance = 0.005;

  ~BagSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// Messages on the first scan topic (cached) times `repeat`; -1 when replaying endlessly.
  int64_t sizeHint() const override;
  /// The raw entries next() writes (for the builder's wiring check).
  std::vector<ProvidedEntry> provides() const override;
  /// Replays started so far (1 during the first pass over the bag).
  int64_t replay() const { return replay_.pass(); }
  /// Frames emitted without odometry (no message within max_odometry_gap).
  std::size_t framesWithoutOdometry() const { return frames_without_odometry_; }
  /// Frames dropped because an image stream had no message within sync_tolerance.
  std::size_t framesDropped() const { return frames_dropped_; }

 protected:
  /// Declares `path` and `mounts` with the format's own descriptions.
  BagSource(const char* path_doc, const char* mounts_doc);

  /// Opens the bag for one pass (configure and every replay).
  virtual void openBag() = 0;
  /// The next message of a mapped topic in this pass, decoded; false at the end of the pass.
  virtual bool readReading(BagReading& reading) = 0;
  /// Every topic of the bag (for the error naming them and the size hint).
  virtual std::vector<BagTopic> bagTopics() const = 0;
  /// "ROS bag 'x.bag'", for messages.
  virtual std::string bagName() const = 0;
  /// At the end of the first pass: the format's own warnings.
  virtual void endOfPass() {}
  /// The bag's rigid transforms (the static tree the mounts come from), read once when a mount
  /// or a sensor's pose is first needed; empty when the bag has none.
  virtual std::vector<BagTransform> rigidTransforms() { return {}; }
  /// Where rigidTransforms() looks, for messages: "/tf_static".
  virtual std::string transformTopics() const { return tf_static(); }
  /// The child_frame_id of the first odometry message ("" = none): the frame odometry moves.
  virtual std::string odometryChildFrame() { return ""; }

  /// The robot frame for a sensor frame: `base_frame`, else the odometry's child frame when the
  /// static tree has it, else the root of the static tree the sensor hangs from.
  std::string robotFrame(const std::string& sensor);
  /// The pose of `frame` in `from` through the static tree, if linked; `path` (when given) gets
  /// the frames crossed with the topic of each edge ("base -> laser (/tf_static)").
  std::optional<Eigen::Isometry3d> staticPose(const std::string& from, const std::string& frame,
                                              std::string* path = nullptr);

  /// Image streams beyond the scans (a source with cameras), checked and appended to the
  /// streams by configure(); may be called before `scans` is read.
  virtual std::vector<BagStream> imageStreams() const { return {}; }

  /// The scan topics and the odometry topic ("" = none), known after configure().
  const std::vector<std::string>& scanTopics() const { return scan_topics_; }
  const std::string& odometryTopic() const { return odom_topic_; }
  /// Every stream, scans first (index = BagReading::stream), known after configure().
  const std::vector<BagStream>& streams() const { return streams_; }

 private:
  struct Stamped {
    double t = 0;
    std::variant<LaserScan, Image, DepthImage> value;
  };
  struct Pose {
    double t = 0;
    Eigen::Isometry2d pose = Eigen::Isometry2d::Identity();
  };
  void open();
  // Reopens the bag for the next replay, keeping the clock going.
  void rewind();
  bool readOne();
  // Builds a frame from the first primary reading; false (reading dropped) when incomplete.
  bool emit(Frame& frame);
  bool ready(double t) const;
  // The odometry at t, stamped with the time it holds for: t when interpolated, else the
  // nearest reading's own stamp (so a motion model can tell a reading taken again from a new one).
  std::optional<Pose> odometryAt(double t) const;
  [[noreturn]] void noFramesError() const;
  // The static tree as undirected edges (a breadth-first search from the robot frame) and each
  // frame's parent, from rigidTransforms(), once per configure().
  void loadStatic();
  // The mount of scan stream i, whose first message is in frame_id: `mounts`, the bag's, or the
  // identity; says which once.
  Eigen::Isometry2d resolveMount(std::size_t i, const std::string& frame_id);
  // The bag's mount of a scanner in frame_id, projected onto the robot's plane; nullopt with the
  // reason in `how`, else the frames used in `how` and the tilt from level in `tilt` [rad].
  std::optional<Eigen::Isometry2d> bagMount(const std::string& frame_id, std::string& how,
                                            double& tilt);

  bool summarized_ = false;  // the end-of-bag warnings were given
  std::vector<std::string> scan_topics_, scan_entries_;
  std::vector<BagStream> streams_;
  std::vector<std::optional<Eigen::Isometry2d>> config_mounts_;  // from `mounts`, if given
  std::vector<std::optional<Eigen::Isometry2d>> scan_mounts_;    // unset: resolveMount() on use
  bool static_loaded_ = false;
  std::multimap<std::string, BagTransform> static_edges_;  // by the frame it leaves, both ways
  std::map<std::string, std::string> static_parent_;
  std::string odom_topic_, odom_entry_;
  bool finished_ = false;
  double latest_stamp_ = 0;  // newest stamp read on any stream
  std::deque<Stamped> primary_;
  std::vector<std::deque<Stamped>> secondary_;  // index i = stream i + 1
  std::deque<Pose> odom_;
  mutable std::optional<int64_t> size_hint_;
  std::size_t frames_without_odometry_ = 0;
  std::size_t frames_dropped_ = 0;
  std::size_t frames_ = 0;
  bool opened_ = false;
  // The pass over the bag and the clock across passes.
  Replay replay_;
};

/// Splits "topic:entry" at its last colon; throws ParamError(param, ...) when malformed.
std::pair<std::string, std::string> splitTopicEntry(const std::string& param,
                                                    const std::string& text);

}  // namespace io
}  // namespace plugslam
