// ROS bag reader (RosbagReader::fromBytes) and the LaserScan / Odometry decoders.
#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "readers/ros_messages.h"
#include "readers/rosbag_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  plugslam::io::RosbagReaderOptions options;
  options.max_record_bytes = 1 << 24;
  try {
    auto reader = plugslam::io::RosbagReader::fromBytes("fuzz.bag",
                                                        plugslam::fuzz::text(data, size), options);
    plugslam::io::RosbagMessage message;
    while (reader->next(message)) {
    }
  } catch (const plugslam::Error&) {
  }
  return 0;
}
