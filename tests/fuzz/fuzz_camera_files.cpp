// The text files of the camera layouts (readers/kitti_files, euroc_files, tum_files). The first
// byte picks the parser: 0 KITTI calibration (+ both rectified pairs), 1 times.txt, 2 KITTI raw
// timestamps, 3 EuRoC data.csv, 4 EuRoC sensor.yaml, 5 EuRoC ground truth, 6 TUM list (+ its
// association with itself), 7 3x3 K matrix, 8 pose list.
#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "readers/euroc_files.h"
#include "readers/kitti_files.h"
#include "readers/tum_files.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string text = plugslam::fuzz::text(data + 1, size - 1);
  namespace io = plugslam::io;
  try {
    switch (data[0] % 9) {
      case 0: {
        const io::KittiCalibration c = io::parseKittiCalibration(text, "calib.txt");
        for (const auto& keys : {std::pair{"P0", "P1"}, std::pair{"P_rect_00", "P_rect_01"}}) {
          try {
            io::rectifiedPair(c, keys.first, keys.second, 640, 480);
          } catch (const plugslam::Error&) {
          }
        }
        break;
      }
      case 1:
        io::parseKittiTimes(text, "times.txt");
        break;
      case 2:
        io::parseKittiRawTimestamps(text, "timestamps.txt");
        break;
      case 3:
        io::parseEurocImageList(text, "data.csv");
        break;
      case 4:
        io::parseEurocSensor(text, "sensor.yaml");
        break;
      case 5:
        io::parseEurocGroundTruth(text, "data.csv");
        break;
      case 6: {
        const auto list = io::parseTumList(text, "rgb.txt");
        io::associateByTime(list, list, 0.02);
        break;
      }
      case 7:
        io::parseIntrinsicsMatrix(text, "camera-intrinsics.txt");
        break;
      default:
        io::parsePoseList(text, "pose.txt");
        break;
    }
  } catch (const plugslam::Error&) {
  }
  return 0;
}
