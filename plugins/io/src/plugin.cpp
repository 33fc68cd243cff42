// The io plugin: dataset sources (CARMEN, ROS1 bags) and the writers.
#include "plugslam/plugin.h"

#include "sources/carmen_source.h"
#include "sources/euroc_source.h"
#include "sources/kitti_raw_source.h"
#include "sources/kitti_source.h"
#include "sources/rgbd_folder_source.h"
#include "sources/tum_rgbd_source.h"
#include "sources/ros2_bag_source.h"
#include "sources/rosbag_source.h"
#include "writers/image_sequence_writer.h"
#include "writers/trajectory_writer.h"

PLUGSLAM_PLUGIN("io", "1.0.0", "dataset sources (CARMEN, ROS 1 and ROS 2 bags, KITTI, EuRoC, TUM RGB-D) and writers") {
  using namespace plugslam::io;
  registrar.add<CarmenSource>("CarmenSource",
                              "CARMEN log (plain, gzip or bzip2): one frame per front laser at "
                              "its own stamp, odometry, a corrected log's poses as reference");
  registrar.add<RosbagSource>("RosbagSource",
                              "ROS1 bag: LaserScan topics + interpolated nav_msgs/Odometry");
  registrar.add<Ros2BagSource>("Ros2BagSource",
                               "ROS 2 bag (MCAP or .db3): LaserScan topics + interpolated "
                               "Odometry, cameras (Image, CompressedImage, depth, CameraInfo), "
                               "mounts from /tf_static");
  registrar.add<KittiSource>("KittiSource",
                             "KITTI odometry layout: rectified stereo, calib.txt, times.txt, poses");
  registrar.add<KittiRawSource>("KittiRawSource",
                                "KITTI raw drive (synced + rectified): stereo, calib_cam_to_cam.txt");
  registrar.add<EurocSource>("EurocSource",
                             "EuRoC MAV layout: raw stereo pairs, sensor.yaml, ground truth");
  registrar.add<TumRgbdSource>("TumRgbdSource",
                               "TUM RGB-D layout: rgb.txt + depth.txt by time, groundtruth.txt");
  registrar.add<RgbdFolderSource>("RgbdFolderSource",
                                  "numbered colour + depth images with a pose list (ICL slambook)");
  registrar.add<TrajectoryWriter>("TrajectoryWriter", "final trajectory as TUM or KITTI");
  registrar.add<ImageSequenceWriter>("ImageSequenceWriter",
                                     "raw images as a KITTI odometry or TUM RGB-D sequence");
}
