// The io plugin: dataset sources (CARMEN, ROS1 bags) and the writers.
#include "plugslam/plugin.h"

#include "sources/carmen_source.h"
#include "sources/rosbag_source.h"
#include "writers/image_sequence_writer.h"
#include "writers/trajectory_writer.h"

PLUGSLAM_PLUGIN("io", "1.0.0", "dataset sources (CARMEN, ROS1 bags) and writers") {
  using namespace plugslam::io;
  registrar.add<CarmenSource>("CarmenSource",
                              "CARMEN log: one frame per front laser, ODOM odometry, logged pose");
  registrar.add<RosbagSource>("RosbagSource",
                              "ROS1 bag: LaserScan topics + interpolated nav_msgs/Odometry");
  registrar.add<TrajectoryWriter>("TrajectoryWriter", "final trajectory as TUM or KITTI");
  registrar.add<ImageSequenceWriter>("ImageSequenceWriter",
                                     "raw images as a KITTI odometry or TUM RGB-D sequence");
}
