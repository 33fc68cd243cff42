// The io plugin: dataset sources (CARMEN, ROS1 bags), the 2D simulator and the writers.
#include "plugslam/plugin.h"

#include "sources/carmen_source.h"
#include "sources/rosbag_source.h"
#include "sources/simulator_source.h"
#include "writers/trajectory_writer.h"

PLUGSLAM_PLUGIN("io", "1.0.0", "dataset sources (CARMEN, ROS1 bags), 2D simulator, writers") {
  using namespace plugslam::io;
  registrar.add<CarmenSource>("CarmenSource",
                              "CARMEN log: one frame per front laser, ODOM odometry, logged pose");
  registrar.add<RosbagSource>("RosbagSource",
                              "ROS1 bag: LaserScan topics + interpolated nav_msgs/Odometry");
  registrar.add<Simulator2DSource>(
      "Simulator2D", "simulated office with lasers, wheel odometry and exact ground truth");
  registrar.add<TrajectoryWriter>("TrajectoryWriter", "final trajectory as TUM or KITTI");
}
