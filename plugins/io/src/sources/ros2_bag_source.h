#pragma once
// io.Ros2BagSource: ROS 2 bags (rosbag2 folders, bare .mcap or .db3 files) of
// sensor_msgs/msg/LaserScan + nav_msgs/msg/Odometry as a frame source.
#include <memory>
#include <string>
#include <vector>

#include "readers/cdr_messages.h"
#include "readers/ros2_bag.h"
#include "sources/bag_source.h"

namespace plugslam {
namespace io {

/// A ROS 2 bag read by Ros2Bag and the CDR decoders; frames, synchronisation and replays exactly
/// as io.RosbagSource (BagSource). Without `mounts`, each scan's mount is its frame's pose in the
/// robot frame composed from the bag's static transforms (/tf_static).
class Ros2BagSource : public BagSource {
 public:
  Param<std::string> tf_static{this, "tf_static", "/tf_static", "",
                               "topic of the static transforms the mounts come from when "
                               "`mounts` is empty; empty = none (identity mounts)"};
  Param<std::string> base_frame{this, "base_frame", "", "",
                                "robot frame of the mounts; empty = the odometry's "
                                "child_frame_id, else the root of the scanner's static tree"};

  Ros2BagSource();
  ~Ros2BagSource() override;

 protected:
  void openBag() override;
  bool readReading(BagReading& reading) override;
  std::vector<BagTopic> bagTopics() const override;
  std::string bagName() const override;
  Eigen::Isometry2d defaultMount(std::size_t index, const std::string& frame_id) override;

 private:
  void checkTopics();
  std::string odometryFrame();
  std::unique_ptr<Ros2Bag> bag_;
};

}  // namespace io
}  // namespace plugslam
