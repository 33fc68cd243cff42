#pragma once
// io.Ros2BagSource: ROS 2 bags (rosbag2 folders, bare .mcap or .db3 files) of
// sensor_msgs/msg/LaserScan + nav_msgs/msg/Odometry, and of cameras (Image, CompressedImage,
// CameraInfo: a mono camera, a stereo pair, RGB-D colour + depth) as a frame source.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "readers/cdr_messages.h"
#include "readers/ros2_bag.h"
#include "sources/bag_source.h"

namespace plugslam {
namespace io {

/// A ROS 2 bag read by Ros2Bag and the CDR decoders; frames, synchronisation and replays exactly
/// as io.RosbagSource (BagSource). Without `mounts`, each scan's mount is its frame's pose in the
/// robot frame composed from the bag's static transforms (/tf_static). Camera topics (`images`,
/// `depth`) are synchronised streams like scans; raw[camera] is the CameraInfo built from the
/// first message of each `camera_info` topic, its mount and second_pose from /tf_static (or the
/// stereo calibration) unless the config gives them.
class Ros2BagSource : public BagSource {
 public:
  Param<std::vector<std::string>> images{
      this, "images", std::vector<std::string>{}, "",
      "Image or CompressedImage topics as \"topic:entry\" (a stereo pair: left, right); the first "
      "paces the frames when `scans` is empty"};
  Param<std::string> depth{this, "depth", "", "",
                           "depth Image topic (16UC1 mm or 32FC1 m) as \"topic:entry\"; empty = "
                           "none"};
  Param<std::vector<std::string>> camera_info{
      this, "camera_info", std::vector<std::string>{}, "",
      "CameraInfo topics: the first image's camera, then the rig's other camera (stereo: the "
      "right one; RGB-D: the depth camera, none = depth registered to colour)"};
  Param<std::string> camera{this, "camera", "camera", "",
                            "raw entry for the calibration (CameraInfo)"};
  Param<std::string> rectified{this,
                               "rectified",
                               "auto",
                               "",
                               "the images are rectified (pinhole from P, no distortion): auto = "
                               "when every CameraInfo has zero distortion, R = I and P = K",
                               Choices{{"auto", "yes", "no"}}};
  Param<std::vector<double>> camera_mount{
      this, "camera_mount", std::vector<double>{}, "m, rad",
      "first camera in the robot frame [x y z rx ry rz] (rotation vector); empty = from "
      "/tf_static"};
  Param<std::vector<double>> second_pose{
      this, "second_pose", std::vector<double>{}, "m, rad",
      "the other camera in the first camera's frame [x y z rx ry rz]; empty = from the stereo "
      "calibration (P, R) or /tf_static"};
  Param<std::string> on_error{this,
                              "on_error",
                              "strict",
                              "",
                              "an image message that does not decode or fit the calibration: "
                              "stop with an error, or warn and skip it",
                              Choices{{"strict", "skip"}}};
  Ros2BagSource();
  ~Ros2BagSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  std::vector<ProvidedEntry> provides() const override;
  /// The calibration of camera frames (after configure(), when `images` is set).
  const CameraInfo& calibration() const { return calibration_; }
  /// Image messages skipped so far (on_error: skip).
  std::size_t skippedImages() const { return skipped_images_; }

 protected:
  std::vector<BagStream> imageStreams() const override;
  void openBag() override;
  bool readReading(BagReading& reading) override;
  std::vector<BagTopic> bagTopics() const override;
  std::string bagName() const override;
  /// Every transform on `tf_static`.
  std::vector<BagTransform> rigidTransforms() override;
  std::string odometryChildFrame() override;

 private:
  void checkTopics();
  void setCalibration();
  // Decodes a camera stream's message into the reading; false when skipped (on_error: skip).
  bool decodeImage(const Ros2Message& m, const BagStream& stream, BagReading& r);

  std::unique_ptr<Ros2Bag> bag_;
  CameraInfo calibration_;
  bool has_camera_ = false;
  std::size_t skipped_images_ = 0;
  bool skips_summarized_ = false;  // the end-of-bag count of skipped images was given
};

}  // namespace io
}  // namespace plugslam
