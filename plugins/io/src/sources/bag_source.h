#pragma once
// The part of the ROS bag sources that does not depend on the bag's format: the topic -> entry
// mapping, the synchronisation of scans and odometry into one frame per primary scan, the mounts
// and the replays. io.RosbagSource (ROS 1) and io.Ros2BagSource (rosbag2, MCAP) read messages
// and hand them over decoded.
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
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

/// One decoded message of a mapped topic.
struct BagReading {
  /// Which stream it belongs to.
  enum class Kind { kScan, kOdometry };
  Kind kind = Kind::kScan;      ///< a scan topic or the odometry topic
  std::size_t scan_index = 0;   ///< index of its scan topic (kScan)
  double record_time = 0;       ///< receipt time [s], used without a header stamp
  LaserScanMsg scan;            ///< kScan
  OdometryMsg odometry;         ///< kOdometry
};

/// One frame per message of the first scan topic, stamped with its header time. The odometry
/// is interpolated at that time between the neighbouring odometry messages (when they are at
/// most max_odometry_gap apart; else the nearest within the gap; else none). Every other scan
/// topic contributes its message nearest in time within sync_tolerance. A bag with no message on
/// the first scan topic is an InputError listing the bag's topics.
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
  /// The mount of scan topic `index` when `mounts` is empty, from the first scan's frame.
  virtual Eigen::Isometry2d defaultMount(std::size_t index, const std::string& frame_id) {
    (void)index;
    (void)frame_id;
    return Eigen::Isometry2d::Identity();
  }

  /// The scan topics and the odometry topic ("" = none), known after configure().
  const std::vector<std::string>& scanTopics() const { return scan_topics_; }
  const std::string& odometryTopic() const { return odom_topic_; }

 private:
  struct Stamped {
    double t = 0;
    LaserScan scan;
  };
  struct Pose {
    double t = 0;
    Eigen::Isometry2d pose = Eigen::Isometry2d::Identity();
  };
  void open();
  // Reopens the bag for the next replay, keeping the clock going.
  void rewind();
  bool readOne();
  bool ready(double t) const;
  std::optional<Eigen::Isometry2d> odometryAt(double t) const;
  [[noreturn]] void noFramesError() const;

  bool summarized_ = false;  // the end-of-bag warnings were given
  std::vector<std::string> scan_topics_, scan_entries_;
  std::vector<std::optional<Eigen::Isometry2d>> scan_mounts_;  // unset: defaultMount() on use
  std::string odom_topic_, odom_entry_;
  bool finished_ = false;
  double latest_stamp_ = 0;  // newest stamp read on any stream
  std::deque<Stamped> primary_;
  std::vector<std::deque<Stamped>> secondary_;  // index i = scan topic i + 1
  std::deque<Pose> odom_;
  mutable std::optional<int64_t> size_hint_;
  std::size_t frames_without_odometry_ = 0;
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
