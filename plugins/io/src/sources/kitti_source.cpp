#include "sources/kitti_source.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "plugslam/errors.h"
#include "images/image_file.h"
#include "readers/kitti_files.h"

namespace plugslam {
namespace io {
namespace fs = std::filesystem;

std::string KittiSource::describe() const { return "KITTI sequence '" + path() + "'"; }

std::string KittiSource::findPoses(const std::string& dir) const {
  if (poses() == "none") return "";
  if (!poses().empty()) return poses();
  std::error_code ec;
  const fs::path folder = fs::absolute(fs::path(dir)).lexically_normal();
  std::string name = folder.filename().string();
  if (name.empty()) name = folder.parent_path().filename().string();
  const bool numbered = !name.empty() && name.find_first_not_of("0123456789") == std::string::npos;
  if (numbered) {
    for (const fs::path& p : {folder / "poses" / (name + ".txt"),
                              folder.parent_path().parent_path() / "poses" / (name + ".txt")})
      if (fs::is_regular_file(p, ec)) return p.string();
  }
  // A folder of another name (a cut, a copy) with one poses file of its own.
  std::vector<fs::path> found;
  if (fs::is_directory(folder / "poses", ec))
    for (const auto& e : fs::directory_iterator(folder / "poses", ec))
      if (e.path().extension() == ".txt") found.push_back(e.path());
  if (found.size() == 1) return found.front().string();
  if (found.size() > 1)
    throw ParamError("poses",
                     "'" + (folder / "poses").string() + "' holds " + std::to_string(found.size()) +
                         " poses files and the folder's name is not a sequence number: name one");
  return "";
}

std::size_t KittiSource::index() {
  checkStereoEntries();
  const std::string dir = folder();
  const bool grey = cameras() == "grey";
  left_dir_ = (fs::path(dir) / (grey ? "image_0" : "image_2")).string();
  right_dir_ = (fs::path(dir) / (grey ? "image_1" : "image_3")).string();
  images_ = listNumberedFiles(left_dir_, ".png");

  const std::string times_file = (fs::path(dir) / "times.txt").string();
  times_ = parseKittiTimes(readTextFile(times_file), times_file);
  if (images_.back().number >= static_cast<int64_t>(times_.size()))
    throw ParseError(times_file, 0,
                     "has " + std::to_string(times_.size()) + " times, but the images go up to " +
                         images_.back().name + ": times.txt is indexed by the image's number");

  // The size is the first image's: calib.txt does not state it.
  const std::string calib_file = (fs::path(dir) / "calib.txt").string();
  const KittiCalibration calib = parseKittiCalibration(readTextFile(calib_file), calib_file);
  const Image first = readImageFile((fs::path(left_dir_) / images_.front().name).string());
  calibration_ = rectifiedPair(calib, grey ? "P0" : "P2", grey ? "P1" : "P3", first.width,
                               first.height);

  poses_.clear();
  const std::string poses_file = findPoses(dir);
  if (!poses_file.empty()) {
    const Trajectory t = readKittiTrajectory(poses_file);
    if (images_.back().number >= static_cast<int64_t>(t.size()))
      throw ParseError(poses_file, 0,
                       "has " + std::to_string(t.size()) + " poses, but the images go up to " +
                           images_.back().name + ": the poses file is indexed by image number");
    for (const auto& p : t) poses_.push_back(p.pose);
    spdlog::info("{}: ground truth from '{}'", describe(), poses_file);
  }
  spdlog::info("{}: {} stereo pairs {}..{} ({}x{}, baseline {:.4f} m)", describe(), images_.size(),
               images_.front().number, images_.back().number, calibration_.width,
               calibration_.height, calibration_.baseline);
  return images_.size();
}

void KittiSource::read(std::size_t i, Frame& frame) {
  const NumberedFile& f = images_[i];
  readStereoPair((fs::path(left_dir_) / f.name).string(),
                 (fs::path(right_dir_) / f.name).string(), times_[static_cast<std::size_t>(f.number)], frame);
}

std::optional<Eigen::Isometry3d> KittiSource::groundTruth(std::size_t i, double) const {
  if (poses_.empty()) return std::nullopt;
  // The poses are camera 0's, which is the robot frame here (the colour pair's mount says where
  // camera 2 sits on it).
  return poses_[static_cast<std::size_t>(images_[i].number)];
}

}  // namespace io
}  // namespace plugslam
