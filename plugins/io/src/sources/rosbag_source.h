#pragma once
// io.RosbagSource: ROS1 bags (sensor_msgs/LaserScan + nav_msgs/Odometry) as a frame source.
#include <memory>
#include <string>
#include <vector>

#include "readers/rosbag_reader.h"
#include "sources/bag_source.h"

namespace plugslam {
namespace io {

/// A ROS1 bag (v2.0) read by RosbagReader; frames, synchronisation and replays as BagSource.
/// Without `mounts`, each scan's mount is its frame's pose in the robot frame composed from the
/// bag's rigid transforms: every edge of `tf_static`, and every edge of `tf` that the bag
/// publishes more than once and never changes (ROS 1 robots often publish their fixed joints
/// on /tf, again and again).
class RosbagSource : public BagSource {
 public:
  Param<std::string> tf{this, "tf", "/tf", "",
                        "topic of the transforms that may move; an edge it publishes more than "
                        "once with always the same value is rigid, a mount like those of "
                        "`tf_static`; empty = none"};

  RosbagSource();
  ~RosbagSource() override;

 protected:
  void openBag() override;
  bool readReading(BagReading& reading) override;
  std::vector<BagTopic> bagTopics() const override;
  std::string bagName() const override;
  void endOfPass() override;
  /// The edges of `tf_static` (the last value of each) and the constant edges of `tf`.
  std::vector<BagTransform> rigidTransforms() override;
  std::string transformTopics() const override;
  std::string odometryChildFrame() override;

 private:
  std::unique_ptr<RosbagReader> reader_;
};

}  // namespace io
}  // namespace plugslam
