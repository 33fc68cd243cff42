#pragma once
// The text files of the KITTI odometry and raw layouts: calib.txt / calib_cam_to_cam.txt
// ("KEY: numbers" lines), times.txt (seconds per line) and the raw timestamps.txt (date + time).
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "readers/text_table.h"

namespace plugslam {
namespace io {

/// A KITTI calibration file: each "KEY: v v v" line by key. Values are parsed when asked for,
/// so a line the reader does not need (calib_time) never fails.
struct KittiCalibration {
  std::string file;                       ///< path, for messages
  std::map<std::string, TextRow> entries;  ///< key -> its values (tokens after the colon)

  /// True when the file has the key.
  bool has(const std::string& key) const { return entries.count(key) > 0; }
  /// The key's values as `count` finite numbers; ParseError naming the file and key when the key
  /// is missing (listing those present) or holds another count.
  std::vector<double> numbers(const std::string& key, std::size_t count) const;
  /// A 3x4 projection matrix (12 numbers, row-major).
  Eigen::Matrix<double, 3, 4> projection(const std::string& key) const;
};

/// Parses a KITTI calibration text; ParseError for a line without "KEY:" or a repeated key.
KittiCalibration parseKittiCalibration(const std::string& text, const std::string& file);

/// A rectified pair from its two projection matrices P = K [I | t] in the rectified reference
/// frame: the left camera's pinhole, width/height, baseline, `second` (the same pinhole) at
/// (baseline, 0, 0), and `mount`: the left camera in the reference camera's frame (identity for
/// P0 / P_rect_00, about 6 cm to the side for KITTI's colour camera 2). ParseError naming the
/// keys when the two K differ or the right camera is not to the right.
CameraInfo rectifiedPair(const KittiCalibration& calib, const std::string& left_key,
                         const std::string& right_key, int width, int height);

/// times.txt: one time in seconds per line.
std::vector<double> parseKittiTimes(const std::string& text, const std::string& file);
/// KITTI raw timestamps.txt: "YYYY-MM-DD HH:MM:SS.fffffffff" per line, as seconds since the
/// Unix epoch (the time is taken as UTC: KITTI does not state its zone).
std::vector<double> parseKittiRawTimestamps(const std::string& text, const std::string& file);

}  // namespace io
}  // namespace plugslam
