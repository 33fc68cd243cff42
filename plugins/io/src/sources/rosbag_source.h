#pragma once
// io.RosbagSource: ROS1 bags (sensor_msgs/LaserScan + nav_msgs/Odometry) as a frame source.
#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "readers/rosbag_reader.h"
#include "sources/replay.h"

namespace plugslam {
namespace io {

/// One frame per message of the first scan topic, stamped with its header time. The odometry
/// is interpolated at that time between the neighbouring odometry messages (when they are at
/// most max_odometry_gap apart; else the nearest within the gap; else none). Every other scan
/// topic contributes its message nearest in time within sync_tolerance. A bag with no message on
/// the first scan topic is an InputError listing the bag's topics.
class RosbagSource : public Source {
 public:
  Param<std::string> path{this, "path", "", "", "ROS1 bag (v2.0) to read"};
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
  Param<std::vector<double>> mounts{
      this, "mounts", {}, "", "x, y, theta (m, m, rad) per scan topic; empty = identity"};
  Param<bool> header_stamps{this, "header_stamps", true, "",
                            "use message header stamps (false: bag record times)"};
  Param<int64_t> repeat{this,
                        "repeat",
                        1,
                        "",
                        "times to play the bag (0: endlessly, until max_frames or Ctrl-C); "
                        "stamps keep increasing across replays",
                        Range{0, 1e9}};

  RosbagSource();
  ~RosbagSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// Messages on the first scan topic (one pass over the bag, cached) times `repeat`; -1 when
  /// replaying endlessly.
  int64_t sizeHint() const override;
  /// The raw entries next() writes (for the builder's wiring check).
  std::vector<ProvidedEntry> provides() const override;
  /// Replays started so far (1 during the first pass over the bag).
  int64_t replay() const { return replay_.pass(); }

  /// Frames emitted without odometry (no message within max_odometry_gap).
  std::size_t framesWithoutOdometry() const { return frames_without_odometry_; }

 private:
  struct Stamped {
    double t = 0;
    LaserScan scan;
  };
  struct Pose {
    double t = 0;
    Eigen::Isometry2d pose = Eigen::Isometry2d::Identity();
  };
  bool summarized_ = false;  // the end-of-bag warnings were given
  void open();
  // Reopens the bag for the next replay, keeping the clock going.
  void rewind();
  bool readOne();
  bool ready(double t) const;
  std::optional<Eigen::Isometry2d> odometryAt(double t) const;
  [[noreturn]] void noFramesError() const;

  std::vector<std::string> scan_topics_, scan_entries_;
  std::vector<Eigen::Isometry2d> scan_mounts_;
  std::string odom_topic_, odom_entry_;
  std::unique_ptr<RosbagReader> reader_;
  bool finished_ = false;
  double latest_stamp_ = 0;  // newest stamp read on any stream
  std::deque<Stamped> primary_;
  std::vector<std::deque<Stamped>> secondary_;  // index i = scan topic i + 1
  std::deque<Pose> odom_;
  mutable std::optional<int64_t> size_hint_;
  std::size_t frames_without_odometry_ = 0;
  std::size_t frames_ = 0;
  // The pass over the bag and the clock across passes.
  Replay replay_;
};

/// Splits "topic:entry" at its last colon; throws ParamError(param, ...) when malformed.
std::pair<std::string, std::string> splitTopicEntry(const std::string& param,
                                                    const std::string& text);

}  // namespace io
}  // namespace plugslam
