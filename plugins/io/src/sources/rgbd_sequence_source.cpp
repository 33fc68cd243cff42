#include "sources/rgbd_sequence_source.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>

#include "plugslam/errors.h"
#include "images/image_file.h"
#include "readers/text_table.h"
#include "readers/tum_files.h"

namespace plugslam {
namespace io {
namespace fs = std::filesystem;

void RgbdSequenceSource::setCalibration(const std::string& dir, const std::string& first_rgb,
                                        const std::string& first_depth) {
  checkEntries({&rgb, &depth});
  double k[4] = {fx(), fy(), cx(), cy()};
  if (!intrinsics_file().empty()) {
    const std::string file = fs::path(intrinsics_file()).is_absolute()
                                 ? intrinsics_file()
                                 : (fs::path(dir) / intrinsics_file()).string();
    const Eigen::Matrix3d K = parseIntrinsicsMatrix(readTextFile(file), file);
    k[0] = K(0, 0);
    k[1] = K(1, 1);
    k[2] = K(0, 2);
    k[3] = K(1, 2);
  } else if (fx() == 0 || fy() == 0) {
    throw ParamError("fx", "set the colour camera's fx, fy, cx, cy, or intrinsics_file");
  }
  mirror_ = Eigen::Vector3d(k[0] < 0 ? -1 : 1, k[1] < 0 ? -1 : 1, 1);
  if (mirror_.x() < 0 || mirror_.y() < 0)
    spdlog::info("{}: negative focal length: mirroring the dataset's {} axis in the camera and "
                 "the world so that both are right-handed",
                 describe(), mirror_.x() < 0 ? (mirror_.y() < 0 ? "x and y" : "x") : "y");

  const Image colour = readImageFile(first_rgb);
  const DepthImage d = readDepthFile(first_depth, depth_scale());
  CameraIntrinsics c;
  c.fx = std::abs(k[0]);
  c.fy = std::abs(k[1]);
  c.cx = k[2];
  c.cy = k[3];
  c.width = colour.width;
  c.height = colour.height;
  if (!parseDistortionModel(distortion_model(), c.distortion.model))
    throw ParamError("distortion_model", "unknown model '" + distortion_model() + "'");
  c.distortion.coefficients = distortion();
  if (c.distortion.model != Distortion::Model::kNone && !c.distortion.valid())
    throw ParamError("distortion", std::to_string(distortion().size()) +
                                       " coefficients do not fit the " + distortion_model() +
                                       " model");
  if (c.distortion.model == Distortion::Model::kNone && !distortion().empty())
    throw ParamError("distortion", "coefficients given with distortion_model: none");
  calibration_.setIntrinsics(c);

  CameraIntrinsics dk;
  if (depth_fx() == 0) {
    dk = c;  // registered: the depth image is in the colour camera's pixels
    if (d.width != c.width || d.height != c.height)
      throw InputError(first_depth + ": depth image is " + std::to_string(d.width) + "x" +
                       std::to_string(d.height) + ", the colour image " +
                       std::to_string(c.width) + "x" + std::to_string(c.height) +
                       ": a registered depth image has the colour image's size (set depth_fx.. "
                       "for a depth camera of its own)");
  } else {
    if (depth_fy() == 0)
      throw ParamError("depth_fy", "set with depth_fx (the depth camera's pinhole)");
    dk.fx = std::abs(depth_fx());
    dk.fy = std::abs(depth_fy());
    dk.cx = depth_cx();
    dk.cy = depth_cy();
    dk.width = d.width;
    dk.height = d.height;
  }
  calibration_.second = dk;
  calibration_.second_pose = Eigen::Isometry3d::Identity();
  if (!depth_pose().empty()) {
    const std::vector<double>& p = depth_pose();
    if (p.size() != 6)
      throw ParamError("depth_pose", "expected 6 numbers [x y z rx ry rz], got " +
                                         std::to_string(p.size()));
    const Eigen::Vector3d r(p[3], p[4], p[5]);
    calibration_.second_pose.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    if (r.norm() > 0)
      calibration_.second_pose.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).matrix();
  }
}

void RgbdSequenceSource::read(std::size_t i, Frame& frame) {
  const RgbdPair& p = pairs_[i];
  frame.stamp = p.stamp;
  readPair(p.rgb, p.depth, p.stamp, frame);
}

void RgbdSequenceSource::readPair(const std::string& rgb_file, const std::string& depth_file,
                                  double stamp, Frame& frame) const {
  readImage(rgb_file, rgb(), stamp, calibration_.width, calibration_.height, frame);
  DepthImage d = readDepthFile(depth_file, depth_scale());
  if (d.width != calibration_.second->width || d.height != calibration_.second->height)
    throw InputError(depth_file + ": depth image is " + std::to_string(d.width) + "x" +
                     std::to_string(d.height) + ", expected " +
                     std::to_string(calibration_.second->width) + "x" +
                     std::to_string(calibration_.second->height));
  d.stamp = stamp;
  frame.raw.set<DepthImage>(depth(), std::move(d));
}

Eigen::Isometry3d RgbdSequenceSource::fromDataset(const Eigen::Isometry3d& pose) const {
  if (mirror_ == Eigen::Vector3d::Ones()) return pose;
  const Eigen::Matrix3d S = mirror_.asDiagonal();
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = S * pose.linear() * S;
  out.translation() = S * pose.translation();
  return out;
}

}  // namespace io
}  // namespace plugslam
