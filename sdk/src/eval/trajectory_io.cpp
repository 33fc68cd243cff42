// Readers and writers of trajectory files. Every malformed line is a ParseError with its line.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "core/enum_names.h"
#include "eval/text_file.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

using eval_detail::format;
using eval_detail::parseNumber;
using eval_detail::readDataLines;
using eval_detail::TextLine;

namespace {

// Quaternions written with few decimals are a few 1e-6 off unit norm; a larger error means the
// columns are not what we think they are.
constexpr double kQuaternionNormTolerance = 1e-2;
constexpr double kRotationTolerance = 1e-3;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

Eigen::Quaterniond checkedQuaternion(const std::string& path, int line, double qx, double qy,
                                     double qz, double qw) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  const double n = q.norm();
  if (std::abs(n - 1.0) > kQuaternionNormTolerance) {
    throw ParseError(path, line, format("quaternion (qx qy qz qw) has norm %.6g, expected 1", n));
  }
  q.normalize();
  return q;
}

void requireColumns(const std::string& path, const TextLine& line, std::size_t expected,
                    const char* layout) {
  if (line.tokens.size() != expected) {
    throw ParseError(
        path, line.number,
        format("expected %zu columns (%s), got %zu", expected, layout, line.tokens.size()));
  }
}

void requireIncreasing(const std::string& path, int line, double prev, double t, bool first) {
  if (first) return;
  if (t < prev) {
    throw ParseError(path, line, format("timestamp %.9f goes backwards (previous %.9f)", t, prev));
  }
  if (t == prev) throw ParseError(path, line, format("duplicate timestamp %.9f", t));
}

void requireNonEmpty(const std::string& path, const Trajectory& trajectory, const char* what) {
  if (trajectory.empty()) throw ParseError(path, 0, std::string("no poses found: ") + what);
}

std::vector<double> readTimes(const std::string& path) {
  std::vector<double> times;
  for (const TextLine& line : readDataLines(path)) {
    requireColumns(path, line, 1, "one timestamp in seconds");
    const double t = parseNumber(path, line, 0, "timestamp");
    requireIncreasing(path, line.number, times.empty() ? 0.0 : times.back(), t, times.empty());
    times.push_back(t);
  }
  if (times.empty()) throw ParseError(path, 0, "no timestamps found: expected one per line");
  return times;
}

std::string tumLine(const StampedPose& p) {
  const Eigen::Vector3d t = p.pose.translation();
  Eigen::Quaterniond q(p.pose.linear());
  q.normalize();
  return format("%.9f %.10g %.10g %.10g %.10g %.10g %.10g %.10g\n", p.t, t.x(), t.y(), t.z(), q.x(),
                q.y(), q.z(), q.w());
}

constexpr EnumName<TrajectoryFormat> kFormatNames[] = {{TrajectoryFormat::Auto, "auto"},
                                                       {TrajectoryFormat::Tum, "tum"},
                                                       {TrajectoryFormat::Kitti, "kitti"},
                                                       {TrajectoryFormat::G2o, "g2o"}};
}  // namespace

std::string toString(TrajectoryFormat format) { return enumName(kFormatNames, format, "auto"); }

TrajectoryFormat parseTrajectoryFormat(const std::string& name) {
  if (const auto format = enumValue(kFormatNames, lower(name))) return *format;
  throw InputError("unknown trajectory format '" + name + "': expected auto, tum, kitti or g2o");
}

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext == ".g2o") return TrajectoryFormat::G2o;
  if (ext == ".tum") return TrajectoryFormat::Tum;
  if (ext == ".kitti") return TrajectoryFormat::Kitti;
  const std::vector<TextLine> lines = readDataLines(path);
  if (lines.empty()) throw ParseError(path, 0, "empty file: no trajectory data");
  const TextLine& first = lines.front();
  const std::string tag = first.tokens.front();
  if (tag.rfind("VERTEX", 0) == 0 || tag.rfind("EDGE", 0) == 0 || tag == "FIX") {
    return TrajectoryFormat::G2o;
  }
  if (first.tokens.size() == 8) return TrajectoryFormat::Tum;
  if (first.tokens.size() == 12) return TrajectoryFormat::Kitti;
  throw ParseError(path, first.number,
                   format("cannot detect the trajectory format: expected 8 numbers (TUM), 12 "
                          "numbers (KITTI) or g2o VERTEX lines, got %zu columns",
                          first.tokens.size()));
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format,
                          const std::string& kitti_times_path) {
  if (format == TrajectoryFormat::Auto) format = detectTrajectoryFormat(path);
  switch (format) {
    case TrajectoryFormat::Tum:
      return readTumTrajectory(path);
    case TrajectoryFormat::Kitti:
      return readKittiTrajectory(path, kitti_times_path);
    case TrajectoryFormat::G2o:
      return readG2oTrajectory(path);
    case TrajectoryFormat::Auto:
      break;
  }
  throw InputError("cannot read '" + path + "': no trajectory format");
}

Trajectory readTumTrajectory(const std::string& path) {
  Trajectory trajectory;
  static const char* kNames[] = {"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
  for (const TextLine& line : readDataLines(path)) {
    requireColumns(path, line, 8, "t x y z qx qy qz qw");
    double v[8];
    for (std::size_t i = 0; i < 8; ++i) v[i] = parseNumber(path, line, i, kNames[i]);
    requireIncreasing(path, line.number, trajectory.empty() ? 0.0 : trajectory.endTime(), v[0],
                      trajectory.empty());
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = checkedQuaternion(path, line.number, v[4], v[5], v[6], v[7]).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    trajectory.push_back(v[0], pose);
  }
  requireNonEmpty(path, trajectory, "expected lines 't x y z qx qy qz qw'");
  return trajectory;
}

Trajectory readKittiTrajectory(const std::string& path, const std::string& times_path) {
  const std::vector<TextLine> lines = readDataLines(path);
  std::vector<double> times;
  if (!times_path.empty()) {
    times = readTimes(times_path);
    if (times.size() != lines.size()) {
      throw InputError(
          format("'%s' has %zu timestamps but '%s' has %zu poses: expected one "
                 "timestamp per pose",
                 times_path.c_str(), times.size(), path.c_str(), lines.size()));
    }
  }
  Trajectory trajectory;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const TextLine& line = lines[k];
    requireColumns(path, line, 12, "a row-major 3x4 matrix r11 r12 r13 tx ... r33 tz");
    Eigen::Matrix<double, 3, 4> m;
    for (std::size_t i = 0; i < 12; ++i) {
      m(static_cast<int>(i / 4), static_cast<int>(i % 4)) =
          parseNumber(path, line, i, "matrix entry");
    }
    const Eigen::Matrix3d r = m.leftCols<3>();
    const double orthogonality = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
    if (orthogonality > kRotationTolerance || r.determinant() < 0.0) {
      throw ParseError(path, line.number,
                       format("the 3x3 block is not a rotation (|R^T R - I| = %.3g, det = %.3g)",
                              orthogonality, r.determinant()));
    }
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
    pose.translation() = m.col(3);
    trajectory.push_back(times.empty() ? static_cast<double>(k) : times[k], pose);
  }
  requireNonEmpty(path, trajectory, "expected lines of 12 numbers (row-major 3x4 pose)");
  return trajectory;
}

Trajectory readG2oTrajectory(const std::string& path) {
  std::map<long long, std::pair<int, Eigen::Isometry3d>> vertices;
  bool has2d = false, has3d = false;
  for (const TextLine& line : readDataLines(path)) {
    const std::string& tag = line.tokens.front();
    const bool se2 = tag == "VERTEX_SE2";
    const bool se3 = tag == "VERTEX_SE3:QUAT";
    if (!se2 && !se3) continue;
    if (se2) {
      requireColumns(path, line, 5, "VERTEX_SE2 id x y theta");
    } else {
      requireColumns(path, line, 9, "VERTEX_SE3:QUAT id x y z qx qy qz qw");
    }
    const double id_value = parseNumber(path, line, 1, "vertex id");
    // Ids become timestamps (doubles): above 2^53 they are no longer distinct, and the cast to
    // an integer below would overflow.
    constexpr double kMaxExactId = 9007199254740992.0;
    if (id_value != std::floor(id_value) || id_value < 0 || id_value > kMaxExactId) {
      throw ParseError(path, line.number,
                       "column 2 (vertex id): expected a non-negative integer up to 2^53, got '" +
                           line.tokens[1] + "'");
    }
    const auto id = static_cast<long long>(id_value);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    if (se2) {
      has2d = true;
      const double x = parseNumber(path, line, 2, "x");
      const double y = parseNumber(path, line, 3, "y");
      const double theta = parseNumber(path, line, 4, "theta");
      pose.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      pose.translation() = Eigen::Vector3d(x, y, 0.0);
    } else {
      has3d = true;
      double v[7];
      static const char* kNames[] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
      for (std::size_t i = 0; i < 7; ++i) v[i] = parseNumber(path, line, i + 2, kNames[i]);
      pose.linear() =
          checkedQuaternion(path, line.number, v[3], v[4], v[5], v[6]).toRotationMatrix();
      pose.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    if (has2d && has3d) {
      throw ParseError(path, line.number,
                       "the graph mixes VERTEX_SE2 and VERTEX_SE3:QUAT: expected one kind");
    }
    auto inserted = vertices.emplace(id, std::make_pair(line.number, pose));
    if (!inserted.second) {
      throw ParseError(path, line.number,
                       format("vertex %lld is defined twice (first on line %d)", id,
                              inserted.first->second.first));
    }
  }
  Trajectory trajectory;
  for (const auto& [id, v] : vertices) trajectory.push_back(static_cast<double>(id), v.second);
  requireNonEmpty(path, trajectory, "expected VERTEX_SE2 or VERTEX_SE3:QUAT lines");
  return trajectory;
}

void writeTumTrajectory(const Trajectory& trajectory, const std::string& path) {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  for (const StampedPose& p : trajectory) text += tumLine(p);
  writeFileAtomically(path, text);
}

void writeKittiTrajectory(const Trajectory& trajectory, const std::string& path,
                          const std::string& times_path) {
  std::string text;
  std::string times;
  for (const StampedPose& p : trajectory) {
    const Eigen::Matrix<double, 3, 4> m = p.pose.matrix().topRows<3>();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) {
        text += format("%.12e", m(r, c));
        text += (r == 2 && c == 3) ? '\n' : ' ';
      }
    }
    times += format("%.9f\n", p.t);
  }
  writeFileAtomically(path, text);
  if (!times_path.empty()) writeFileAtomically(times_path, times);
}

}  // namespace abi_v1
}  // namespace plugslam
