#include "sources/kitti_raw_source.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>

#include "plugslam/errors.h"
#include "images/image_file.h"
#include "readers/kitti_files.h"

namespace plugslam {
namespace io {
namespace fs = std::filesystem;

std::string KittiRawSource::describe() const { return "KITTI raw drive '" + path() + "'"; }

std::size_t KittiRawSource::index() {
  checkStereoEntries();
  const std::string dir = folder();
  const bool grey = cameras() == "grey";
  const std::string l = grey ? "00" : "02", r = grey ? "01" : "03";
  left_dir_ = (fs::path(dir) / ("image_" + l) / "data").string();
  right_dir_ = (fs::path(dir) / ("image_" + r) / "data").string();
  images_ = listNumberedFiles(left_dir_, ".png");

  const std::string times_file = (fs::path(dir) / ("image_" + l) / "timestamps.txt").string();
  times_ = parseKittiRawTimestamps(readTextFile(times_file), times_file);
  if (images_.back().number >= static_cast<int64_t>(times_.size()))
    throw ParseError(times_file, 0,
                     "has " + std::to_string(times_.size()) + " timestamps, but the images go up " +
                         "to " + images_.back().name + ": the file is indexed by image number");

  // The official layout keeps the calibration in the date folder above the drive.
  std::error_code ec;
  fs::path calib_file = fs::path(dir) / "calib_cam_to_cam.txt";
  if (!fs::is_regular_file(calib_file, ec)) {
    const fs::path up =
        fs::absolute(fs::path(dir)).lexically_normal().parent_path() / "calib_cam_to_cam.txt";
    if (fs::is_regular_file(up, ec)) calib_file = up;
  }
  const KittiCalibration calib = parseKittiCalibration(readTextFile(calib_file.string()),
                                                       calib_file.string());
  const std::vector<double> size = calib.numbers("S_rect_" + l, 2);
  const int width = static_cast<int>(std::lround(size[0]));
  const int height = static_cast<int>(std::lround(size[1]));
  if (width <= 0 || height <= 0 || width > 65536 || height > 65536)
    throw ParseError(calib_file.string(), calib.entries.at("S_rect_" + l).line,
                     "S_rect_" + l + ": expected the image width and height in pixels");
  calibration_ = rectifiedPair(calib, "P_rect_" + l, "P_rect_" + r, width, height);
  spdlog::info("{}: {} stereo pairs {}..{} ({}x{}, baseline {:.4f} m)", describe(), images_.size(),
               images_.front().number, images_.back().number, width, height,
               calibration_.baseline);
  return images_.size();
}

void KittiRawSource::read(std::size_t i, Frame& frame) {
  const NumberedFile& f = images_[i];
  readStereoPair((fs::path(left_dir_) / f.name).string(),
                 (fs::path(right_dir_) / f.name).string(), times_[static_cast<std::size_t>(f.number)], frame);
}

}  // namespace io
}  // namespace plugslam
