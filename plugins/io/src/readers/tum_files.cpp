#include "readers/tum_files.h"

#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"
#include "readers/text_table.h"

namespace plugslam {
namespace io {

std::vector<TumListEntry> parseTumList(const std::string& text, const std::string& file) {
  std::vector<TumListEntry> list;
  for (const TextRow& row : dataRows(text, " \t")) {
    if (row.tokens.size() != 2)
      throw ParseError(file, row.line,
                       "expected 'timestamp filename', got " + std::to_string(row.tokens.size()) +
                           " columns");
    TumListEntry e;
    e.stamp = rowNumber(file, row, 0, "timestamp [s]");
    e.file = row.tokens[1];
    e.line = row.line;
    if (!list.empty() && e.stamp < list.back().stamp)
      throw ParseError(file, row.line, "timestamp goes backwards");
    list.push_back(std::move(e));
  }
  return list;
}

std::vector<TumPair> associateByTime(const std::vector<TumListEntry>& rgb,
                                     const std::vector<TumListEntry>& depth,
                                     double max_difference) {
  // Candidates within the tolerance, by a sliding window over the two sorted lists.
  struct Candidate {
    double diff;
    std::size_t rgb, depth;
  };
  std::vector<Candidate> candidates;
  std::size_t lo = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    while (lo < depth.size() && depth[lo].stamp <= rgb[i].stamp - max_difference) ++lo;
    for (std::size_t j = lo; j < depth.size() && depth[j].stamp < rgb[i].stamp + max_difference;
         ++j)
      candidates.push_back({std::abs(rgb[i].stamp - depth[j].stamp), i, j});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.diff < b.diff; });
  std::vector<char> rgb_used(rgb.size(), 0), depth_used(depth.size(), 0);
  std::vector<TumPair> pairs;
  for (const Candidate& c : candidates) {
    if (rgb_used[c.rgb] || depth_used[c.depth]) continue;
    rgb_used[c.rgb] = depth_used[c.depth] = 1;
    pairs.push_back({c.rgb, c.depth});
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const TumPair& a, const TumPair& b) { return a.rgb < b.rgb; });
  return pairs;
}

Eigen::Matrix3d parseIntrinsicsMatrix(const std::string& text, const std::string& file) {
  const std::vector<TextRow> rows = dataRows(text, " \t,");
  if (rows.size() != 3)
    throw ParseError(file, rows.empty() ? 0 : rows.back().line,
                     "expected a 3x3 camera matrix (3 rows of 3 numbers), got " +
                         std::to_string(rows.size()) + " rows");
  Eigen::Matrix3d K;
  for (int r = 0; r < 3; ++r) {
    if (rows[r].tokens.size() != 3)
      throw ParseError(file, rows[r].line,
                       "expected 3 numbers in a row of the camera matrix, got " +
                           std::to_string(rows[r].tokens.size()));
    for (int c = 0; c < 3; ++c)
      K(r, c) = rowNumber(file, rows[r], static_cast<std::size_t>(c), "camera matrix entry");
  }
  const bool shape = K(0, 1) == 0 && K(1, 0) == 0 && K(2, 0) == 0 && K(2, 1) == 0 &&
                     K(2, 2) == 1 && K(0, 0) != 0 && K(1, 1) != 0;
  if (!shape)
    throw ParseError(file, rows[0].line,
                     "expected a camera matrix [fx 0 cx; 0 fy cy; 0 0 1] with fx, fy != 0");
  return K;
}

std::vector<Eigen::Isometry3d> parsePoseList(const std::string& text, const std::string& file) {
  std::vector<Eigen::Isometry3d> poses;
  for (const TextRow& row : dataRows(text, " \t,")) {
    if (row.tokens.size() != 7)
      throw ParseError(file, row.line,
                       "expected 7 columns (tx ty tz qx qy qz qw), got " +
                           std::to_string(row.tokens.size()));
    double v[7];
    static const char* kNames[7] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    for (int k = 0; k < 7; ++k) v[k] = rowNumber(file, row, static_cast<std::size_t>(k), kNames[k]);
    Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw ParseError(file, row.line,
                       "quaternion (qx qy qz qw) has norm " + std::to_string(q.norm()) +
                           ", expected 1");
    q.normalize();
    poses.push_back(Eigen::Translation3d(v[0], v[1], v[2]) * q);
  }
  return poses;
}

}  // namespace io
}  // namespace plugslam
