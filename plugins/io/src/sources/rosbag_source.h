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
class RosbagSource : public BagSource {
 public:
  RosbagSource();
  ~RosbagSource() override;

 protected:
  void openBag() override;
  bool readReading(BagReading& reading) override;
  std::vector<BagTopic> bagTopics() const override;
  std::string bagName() const override;
  void endOfPass() override;

 private:
  std::unique_ptr<RosbagReader> reader_;
};

}  // namespace io
}  // namespace plugslam
