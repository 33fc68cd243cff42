#include "readers/euroc_files.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>

#include "plugslam/errors.h"
#include "plugslam/yaml_load.h"
#include "readers/text_table.h"

namespace plugslam {
namespace io {

std::vector<EurocImage> parseEurocImageList(const std::string& text, const std::string& file) {
  std::vector<EurocImage> images;
  for (const TextRow& row : dataRows(text, ",")) {
    if (row.tokens.size() != 2)
      throw ParseError(file, row.line,
                       "expected 2 columns (timestamp [ns], filename), got " +
                           std::to_string(row.tokens.size()));
    EurocImage im;
    im.stamp_ns = rowInteger(file, row, 0, "timestamp [ns]");
    im.file = row.tokens[1];
    while (!im.file.empty() && (im.file.back() == ' ' || im.file.back() == '\t'))
      im.file.pop_back();
    while (!im.file.empty() && (im.file.front() == ' ' || im.file.front() == '\t'))
      im.file.erase(im.file.begin());
    if (im.file.empty() || im.file.find('/') != std::string::npos)
      throw ParseError(file, row.line, "expected a file name in camN/data/, got '" + im.file + "'");
    im.line = row.line;
    if (!images.empty() && im.stamp_ns <= images.back().stamp_ns)
      throw ParseError(file, row.line,
                       "timestamp " + std::to_string(im.stamp_ns) + " does not follow " +
                           std::to_string(images.back().stamp_ns));
    images.push_back(std::move(im));
  }
  return images;
}

namespace {

int lineOf(const YAML::Node& n) { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }

std::vector<double> numberList(const YAML::Node& root, const std::string& key, std::size_t n,
                               const std::string& file) {
  const YAML::Node node = root[key];
  if (!node) throw ParseError(file, 0, "missing key '" + key + "'");
  if (!node.IsSequence() || (n != 0 && node.size() != n))
    throw ParseError(file, lineOf(node),
                     key + ": expected a list of " + (n ? std::to_string(n) + " " : "") +
                         "numbers");
  std::vector<double> v;
  for (const auto& x : node) {
    double d = 0;
    try {
      d = x.as<double>();
    } catch (const YAML::Exception&) {
      throw ParseError(file, lineOf(x), key + ": '" + (x.IsScalar() ? x.Scalar() : "?") +
                                            "' is not a number");
    }
    if (!std::isfinite(d)) throw ParseError(file, lineOf(x), key + ": values must be finite");
    v.push_back(d);
  }
  return v;
}

std::string scalar(const YAML::Node& root, const std::string& key, const std::string& file) {
  const YAML::Node node = root[key];
  if (!node) throw ParseError(file, 0, "missing key '" + key + "'");
  if (!node.IsScalar()) throw ParseError(file, lineOf(node), key + ": expected a name");
  return node.Scalar();
}

}  // namespace

EurocCamera parseEurocSensor(const std::string& text, const std::string& file) {
  // OpenCV's FileStorage writes "%YAML:1.0", which is not a YAML directive.
  std::string yaml = text;
  if (yaml.rfind("%YAML:", 0) == 0) yaml[0] = '#';
  YAML::Node root;
  try {
    root = loadYaml(yaml);
  } catch (const YAML::Exception& e) {
    throw ParseError(file, e.mark.line >= 0 ? e.mark.line + 1 : 0, "invalid YAML: " + e.msg);
  }
  if (!root.IsMap()) throw ParseError(file, 0, "expected a map of sensor keys");
  EurocCamera cam;
  try {
    const std::string model = scalar(root, "camera_model", file);
    if (model != "pinhole")
      throw ParseError(file, lineOf(root["camera_model"]),
                       "camera_model '" + model + "' is not supported (expected pinhole)");
    const YAML::Node T = root["T_BS"];
    if (!T) throw ParseError(file, 0, "missing key 'T_BS'");
    if (!T.IsMap()) throw ParseError(file, lineOf(T), "T_BS: expected {cols, rows, data}");
    const std::vector<double> data = numberList(T, "data", 16, file);
    Eigen::Matrix4d M;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) M(r, c) = data[static_cast<std::size_t>(4 * r + c)];
    const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
    if (!(R.transpose() * R - Eigen::Matrix3d::Identity()).isZero(1e-6) || R.determinant() < 0 ||
        !M.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)))
      throw ParseError(file, lineOf(T), "T_BS is not a rigid transform (rotation + translation)");
    // Re-orthonormalise the 1e-12-level rounding of the printed rotation.
    Eigen::Quaterniond q(R);
    q.normalize();
    cam.T_BS = Eigen::Translation3d(M.topRightCorner<3, 1>()) * q;

    const std::vector<double> res = numberList(root, "resolution", 2, file);
    const std::vector<double> k = numberList(root, "intrinsics", 4, file);
    CameraIntrinsics& in = cam.intrinsics;
    // Checked as doubles: casting a value outside int's range is undefined behaviour.
    for (std::size_t i = 0; i < 2; ++i) {
      if (!(res[i] >= 1 && res[i] <= 65536 && res[i] == std::floor(res[i]))) {
        std::ostringstream got;
        got << res[i];
        throw ParseError(file, lineOf(root["resolution"][i]),
                         std::string("resolution: expected [width, height] in whole pixels from 1 "
                                     "to 65536, got ") +
                             (i == 0 ? "width " : "height ") + got.str());
      }
    }
    in.width = static_cast<int>(res[0]);
    in.height = static_cast<int>(res[1]);
    in.fx = k[0];
    in.fy = k[1];
    in.cx = k[2];
    in.cy = k[3];
    if (!(in.fx > 0) || !(in.fy > 0))
      throw ParseError(file, lineOf(root["intrinsics"]),
                       "intrinsics: expected [fu, fv, cu, cv] with fu, fv > 0");
    const std::string dist = scalar(root, "distortion_model", file);
    if (!parseDistortionModel(dist, in.distortion.model))
      throw ParseError(file, lineOf(root["distortion_model"]),
                       "distortion_model '" + dist +
                           "' is not known (radial-tangential or equidistant)");
    in.distortion.coefficients = numberList(root, "distortion_coefficients", 0, file);
    if (!in.distortion.valid())
      throw ParseError(file, lineOf(root["distortion_coefficients"]),
                       "distortion_coefficients: " +
                           std::to_string(in.distortion.coefficients.size()) +
                           " values do not fit the " + dist + " model");
  } catch (const YAML::Exception& e) {
    throw ParseError(file, e.mark.line >= 0 ? e.mark.line + 1 : 0, e.msg);
  }
  return cam;
}

Trajectory parseEurocGroundTruth(const std::string& text, const std::string& file) {
  std::vector<StampedPose> poses;
  for (const TextRow& row : dataRows(text, ",")) {
    requireColumns(file, row, 8, "timestamp [ns], p_x, p_y, p_z, q_w, q_x, q_y, q_z");
    StampedPose p;
    p.t = static_cast<double>(rowInteger(file, row, 0, "timestamp [ns]")) * 1e-9;
    const Eigen::Vector3d t(rowNumber(file, row, 1, "p_x"), rowNumber(file, row, 2, "p_y"),
                            rowNumber(file, row, 3, "p_z"));
    Eigen::Quaterniond q(rowNumber(file, row, 4, "q_w"), rowNumber(file, row, 5, "q_x"),
                         rowNumber(file, row, 6, "q_y"), rowNumber(file, row, 7, "q_z"));
    if (std::abs(q.norm() - 1.0) > 1e-3)
      throw ParseError(file, row.line,
                       "quaternion (q_w q_x q_y q_z) has norm " + std::to_string(q.norm()) +
                           ", expected 1");
    q.normalize();
    p.pose = Eigen::Translation3d(t) * q;
    if (!poses.empty() && p.t <= poses.back().t)
      throw ParseError(file, row.line, "timestamp does not follow the previous row's");
    poses.push_back(p);
  }
  return Trajectory(std::move(poses));
}

}  // namespace io
}  // namespace plugslam
