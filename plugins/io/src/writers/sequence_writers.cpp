#include "writers/sequence_writers.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "images/png.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"

namespace plugslam {
namespace io {
namespace {

namespace fs = std::filesystem;

void makeDirs(const fs::path& p) {
  std::error_code ec;
  fs::create_directories(p, ec);
  if (ec) throw InputError("cannot create folder '" + p.string() + "': " + ec.message());
}

// Index files are written last and atomically: a folder whose index exists is complete.
void writeText(const fs::path& p, const std::string& text) {
  writeFileAtomically(p.string(), [&](std::ostream& out) { out << text; });
}

// TUM names files by their stamp with 6 decimals.
std::string stampName(double t) { return fmt::format("{:.6f}", t); }

}  // namespace

KittiWriter::KittiWriter(std::string dir, const CameraInfo& camera, std::string sequence)
    : dir_(std::move(dir)), camera_(camera), sequence_(std::move(sequence)) {
  if (!(camera_.baseline > 0.0))
    throw InputError("KittiWriter: the camera needs a stereo baseline");
  if (sequence_.empty() || sequence_.find('/') != std::string::npos)
    throw InputError("KittiWriter: the sequence name must be a plain file name like 00");
  makeDirs(fs::path(dir_) / "image_0");
  makeDirs(fs::path(dir_) / "image_1");
  makeDirs(fs::path(dir_) / "poses");
}

void KittiWriter::add(double stamp, const Image& left, const Image& right,
                      const Eigen::Isometry3d& pose) {
  if (left.channels != 1 || right.channels != 1)
    throw InputError("KittiWriter: KITTI odometry images are 8-bit grey (1 channel)");
  const std::string name = fmt::format("{:06d}.png", stamps_.size());
  writePng((fs::path(dir_) / "image_0" / name).string(), left);
  writePng((fs::path(dir_) / "image_1" / name).string(), right);
  stamps_.push_back(stamp);
  poses_.push_back(pose);
}

void KittiWriter::finish() {
  const CameraInfo& c = camera_;
  auto P = [&](double tx) {
    return fmt::format("{:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e} {:e}", c.fx, 0.0,
                       c.cx, tx, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0);
  };
  const std::string p0 = P(0.0), p1 = P(-c.fx * c.baseline);
  writeText(fs::path(dir_) / "calib.txt",
            "P0: " + p0 + "\nP1: " + p1 + "\nP2: " + p0 + "\nP3: " + p1 +
                "\nTr: 1.000000e+00 0.000000e+00 0.000000e+00 0.000000e+00 0.000000e+00 "
                "1.000000e+00 0.000000e+00 0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00 "
                "0.000000e+00\n");
  // KITTI poses are the left camera in the frame of the first left camera.
  Trajectory relative;
  const double t0 = stamps_.empty() ? 0.0 : stamps_.front();
  std::string times;
  for (size_t k = 0; k < stamps_.size(); ++k) {
    relative.push_back(static_cast<double>(k), poses_.front().inverse() * poses_[k]);
    times += fmt::format("{:e}\n", stamps_[k] - t0);
  }
  writeText(fs::path(dir_) / "times.txt", times);
  writeKittiTrajectory(relative, (fs::path(dir_) / "poses" / (sequence_ + ".txt")).string());
}

TumWriter::TumWriter(std::string dir, double depth_scale)
    : dir_(std::move(dir)), depth_scale_(depth_scale) {
  if (!(depth_scale_ > 0.0)) throw InputError("TumWriter: depth_scale must be positive");
  makeDirs(fs::path(dir_) / "rgb");
  makeDirs(fs::path(dir_) / "depth");
}

void TumWriter::add(double stamp, const Image& rgb, const DepthImage& depth,
                    const Eigen::Isometry3d& pose) {
  if (rgb.channels != 3) throw InputError("TumWriter: TUM RGB-D colour images have 3 channels");
  if (depth.width != rgb.width || depth.height != rgb.height)
    throw InputError("TumWriter: the depth image must have the colour image's size");
  if (!stamps_.empty() && !(stamp > stamps_.back()))
    throw InputError("TumWriter: stamps must increase");
  const std::string name = stampName(stamp) + ".png";
  writePng((fs::path(dir_) / "rgb" / name).string(), rgb);
  writePng16((fs::path(dir_) / "depth" / name).string(), depth.width, depth.height,
             depthToUint16(depth, depth_scale_));
  stamps_.push_back(stamp);
  poses_.push_back(stamp, pose);
}

void TumWriter::finish() {
  std::string rgb = "# color images\n# simulated by plugslam sim3d\n# timestamp filename\n";
  std::string depth = "# depth maps\n# simulated by plugslam sim3d\n# timestamp filename\n";
  for (double t : stamps_) {
    rgb += stampName(t) + " rgb/" + stampName(t) + ".png\n";
    depth += stampName(t) + " depth/" + stampName(t) + ".png\n";
  }
  writeText(fs::path(dir_) / "rgb.txt", rgb);
  writeText(fs::path(dir_) / "depth.txt", depth);
  writeTumTrajectory(poses_, (fs::path(dir_) / "groundtruth.txt").string());
}

}  // namespace io
}  // namespace plugslam
