#include "readers/kitti_files.h"

#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {

std::vector<double> KittiCalibration::numbers(const std::string& key, std::size_t count) const {
  auto it = entries.find(key);
  if (it == entries.end()) {
    std::string present;
    for (const auto& [k, row] : entries) present += (present.empty() ? "" : ", ") + k;
    throw ParseError(file, 0,
                     "missing key '" + key + "' (keys present: " +
                         (present.empty() ? std::string("none") : present) + ")");
  }
  const TextRow& row = it->second;
  if (row.tokens.size() != count)
    throw ParseError(file, row.line,
                     key + ": expected " + std::to_string(count) + " numbers, got " +
                         std::to_string(row.tokens.size()));
  std::vector<double> v(count);
  const std::string what = key + " value";
  for (std::size_t i = 0; i < count; ++i) v[i] = rowNumber(file, row, i, what.c_str());
  return v;
}

Eigen::Matrix<double, 3, 4> KittiCalibration::projection(const std::string& key) const {
  const std::vector<double> v = numbers(key, 12);
  Eigen::Matrix<double, 3, 4> P;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) P(r, c) = v[static_cast<std::size_t>(4 * r + c)];
  return P;
}

KittiCalibration parseKittiCalibration(const std::string& text, const std::string& file) {
  KittiCalibration calib;
  calib.file = file;
  for (TextRow& row : dataRows(text, " \t")) {
    std::string& first = row.tokens.front();
    const std::size_t colon = first.find(':');
    if (colon == std::string::npos || colon == 0)
      throw ParseError(file, row.line, "expected 'KEY: values', got '" + first + "'");
    std::string key = first.substr(0, colon);
    std::string rest = first.substr(colon + 1);
    row.tokens.erase(row.tokens.begin());
    if (!rest.empty()) row.tokens.insert(row.tokens.begin(), rest);
    if (calib.entries.count(key))
      throw ParseError(file, row.line, "key '" + key + "' appears twice");
    calib.entries.emplace(std::move(key), std::move(row));
  }
  return calib;
}

CameraInfo rectifiedPair(const KittiCalibration& calib, const std::string& left_key,
                         const std::string& right_key, int width, int height) {
  const Eigen::Matrix<double, 3, 4> Pl = calib.projection(left_key);
  const Eigen::Matrix<double, 3, 4> Pr = calib.projection(right_key);
  const Eigen::Matrix3d K = Pl.leftCols<3>();
  const double scale = K.cwiseAbs().maxCoeff();
  if (!(K(0, 0) > 0) || !(K(1, 1) > 0) || std::abs(K(1, 0)) > 1e-9 * scale ||
      std::abs(K(2, 0)) > 1e-9 * scale || std::abs(K(2, 1)) > 1e-9 * scale ||
      std::abs(K(2, 2) - 1.0) > 1e-9)
    throw ParseError(calib.file, calib.entries.at(left_key).line,
                     left_key + " is not a pinhole projection K [I | t] (fx, fy > 0, last row 0 0 1)");
  if (!(Pr.leftCols<3>() - K).isZero(1e-6 * scale))
    throw ParseError(calib.file, calib.entries.at(right_key).line,
                     left_key + " and " + right_key +
                         " have different intrinsics: not a rectified pair");
  // P = K [I | t]: t = K^-1 P.col(3) takes reference-frame points into the camera, whose centre
  // in the reference frame is therefore -t.
  const Eigen::Vector3d cl = -K.inverse() * Pl.col(3);
  const Eigen::Vector3d cr = -K.inverse() * Pr.col(3);
  const Eigen::Vector3d offset = cr - cl;
  // KITTI's colour P2/P3 place the cameras a few millimetres apart in y and z as well (0.7 % of
  // the baseline): rectified to one rotation, and accepted as a row-aligned pair.
  if (!(offset.x() > 0) || std::abs(offset.y()) > 0.02 * offset.x() ||
      std::abs(offset.z()) > 0.02 * offset.x())
    throw ParseError(calib.file, calib.entries.at(right_key).line,
                     right_key + " does not place its camera to the right of " + left_key +
                         " along x (offset " + std::to_string(offset.x()) + ", " +
                         std::to_string(offset.y()) + ", " + std::to_string(offset.z()) + " m)");
  CameraInfo c;
  c.fx = K(0, 0);
  c.fy = K(1, 1);
  c.cx = K(0, 2);
  c.cy = K(1, 2);
  c.width = width;
  c.height = height;
  c.baseline = offset.x();
  c.mount = Eigen::Translation3d(cl);
  CameraIntrinsics right = c.intrinsics();
  c.second = right;
  c.second_pose = Eigen::Translation3d(c.baseline, 0.0, 0.0);
  return c;
}

std::vector<double> parseKittiTimes(const std::string& text, const std::string& file) {
  std::vector<double> times;
  for (const TextRow& row : dataRows(text, " \t")) {
    if (row.tokens.size() != 1)
      throw ParseError(file, row.line,
                       "expected one time in seconds per line, got " +
                           std::to_string(row.tokens.size()) + " values");
    times.push_back(rowNumber(file, row, 0, "time [s]"));
    if (static_cast<int>(times.size()) != row.line)
      throw ParseError(file, row.line,
                       "blank or comment line before it: times.txt is indexed by line, one per "
                       "image number");
  }
  return times;
}

namespace {

// Days from 1970-01-01 to y-m-d in the proleptic Gregorian calendar (H. Hinnant's algorithm).
long long daysFromCivil(long long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}

}  // namespace

namespace {

// Reads `n` digits at s[i..]; false when one is not a digit.
bool digits(const std::string& s, std::size_t i, std::size_t n, int& out) {
  if (i + n > s.size()) return false;
  out = 0;
  for (std::size_t k = i; k < i + n; ++k) {
    if (s[k] < '0' || s[k] > '9') return false;
    out = out * 10 + (s[k] - '0');
  }
  return true;
}

// "YYYY-MM-DD HH:MM:SS[.f...]" (up to 9 fraction digits) as seconds since the epoch, UTC.
bool parseDateTime(const std::string& s, double& seconds) {
  int y, mo, d, h, mi, sec;
  if (!digits(s, 0, 4, y) || s.size() < 19 || s[4] != '-' || !digits(s, 5, 2, mo) ||
      s[7] != '-' || !digits(s, 8, 2, d) || s[10] != ' ' || !digits(s, 11, 2, h) ||
      s[13] != ':' || !digits(s, 14, 2, mi) || s[16] != ':' || !digits(s, 17, 2, sec))
    return false;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || sec > 60) return false;
  long long ns = 0;
  if (s.size() > 19) {
    const std::size_t n = s.size() - 20;
    if (s[19] != '.' || n == 0 || n > 9) return false;
    int digit;
    for (std::size_t k = 0; k < 9; ++k) {
      if (k < n && !digits(s, 20 + k, 1, digit)) return false;
      ns = ns * 10 + (k < n ? digit : 0);
    }
  }
  const long long days = daysFromCivil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d));
  seconds = static_cast<double>(days * 86400 + h * 3600LL + mi * 60LL + sec) +
            static_cast<double>(ns) * 1e-9;
  return true;
}

}  // namespace

std::vector<double> parseKittiRawTimestamps(const std::string& text, const std::string& file) {
  std::vector<double> times;
  for (const TextRow& row : dataRows(text, " \t")) {
    std::string joined;
    for (const std::string& t : row.tokens) joined += (joined.empty() ? "" : " ") + t;
    double t = 0;
    if (row.tokens.size() != 2 || !parseDateTime(joined, t))
      throw ParseError(file, row.line,
                       "expected 'YYYY-MM-DD HH:MM:SS.fffffffff', got '" + joined + "'");
    times.push_back(t);
    if (static_cast<int>(times.size()) != row.line)
      throw ParseError(file, row.line,
                       "blank or comment line before it: timestamps.txt is indexed by line, one "
                       "per image number");
  }
  return times;
}

}  // namespace io
}  // namespace plugslam
