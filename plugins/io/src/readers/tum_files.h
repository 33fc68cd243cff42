#pragma once
// The index files of the TUM RGB-D layout (rgb.txt, depth.txt: "timestamp filename" rows) and
// their association by time, a 3x3 intrinsics matrix file (7-Scenes' camera-intrinsics.txt) and
// a stamp-less pose list ("tx ty tz qx qy qz qw" per line, slambook's pose.txt).
#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

namespace plugslam {
namespace io {

/// One row of rgb.txt / depth.txt.
struct TumListEntry {
  double stamp = 0;  ///< [s]
  std::string file;  ///< path relative to the dataset folder
  int line = 0;      ///< 1-based line in the list
};

/// Parses a TUM list; ParseError for a malformed row or a time that goes backwards.
std::vector<TumListEntry> parseTumList(const std::string& text, const std::string& file);

/// A colour image and the depth image taken with it (indices into the two lists).
struct TumPair {
  std::size_t rgb = 0;    ///< index in the colour list
  std::size_t depth = 0;  ///< index in the depth list
};

/// Pairs colour and depth by time as TUM's associate.py does: the closest pairs first, each
/// image used once, |t_rgb - t_depth| < max_difference; the result in colour-time order.
std::vector<TumPair> associateByTime(const std::vector<TumListEntry>& rgb,
                                     const std::vector<TumListEntry>& depth,
                                     double max_difference);

/// A 3x3 camera matrix K written as 3 rows of 3 numbers; ParseError unless it is
/// [fx 0 cx; 0 fy cy; 0 0 1] with fx, fy != 0.
Eigen::Matrix3d parseIntrinsicsMatrix(const std::string& text, const std::string& file);

/// One pose per line, "tx ty tz qx qy qz qw" (camera to world), without timestamps.
std::vector<Eigen::Isometry3d> parsePoseList(const std::string& text, const std::string& file);

}  // namespace io
}  // namespace plugslam
