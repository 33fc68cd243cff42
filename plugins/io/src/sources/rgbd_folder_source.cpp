#include "sources/rgbd_folder_source.h"

#include <filesystem>
#include <map>

#include "plugslam/errors.h"
#include "readers/text_table.h"
#include "readers/tum_files.h"

namespace plugslam {
namespace io {
namespace fs = std::filesystem;

std::string RgbdFolderSource::describe() const { return "RGB-D folder '" + path() + "'"; }

std::size_t RgbdFolderSource::index() {
  const fs::path dir = folder();
  const fs::path cdir = dir / colour_folder(), ddir = dir / depth_folder();
  const auto colour = listNumberedFiles(cdir.string(), colour_extension());
  std::map<int64_t, std::string> depth;
  for (const auto& f : listNumberedFiles(ddir.string(), ".png")) depth[f.number] = f.name;
  // Every colour image is a frame: one whose depth image is missing is a bad frame (an error
  // naming the file and frame, or skipped with on_error: skip), as a missing image of the other
  // layouts is, and the pose list stays one line per colour image.
  pairs_.clear();
  const RgbdPair* calibrated = nullptr;
  for (const auto& f : colour) {
    auto it = depth.find(f.number);
    const std::string d = it != depth.end() ? it->second : std::to_string(f.number) + ".png";
    pairs_.push_back({static_cast<double>(pairs_.size()) / rate(), (cdir / f.name).string(),
                      (ddir / d).string()});
  }
  for (const auto& p : pairs_)
    if (!calibrated && fs::is_regular_file(p.depth)) calibrated = &p;
  if (!calibrated)
    throw InputError(describe() + ": no colour image in '" + cdir.string() +
                     "' has a depth image of the same number in '" + ddir.string() + "'");
  setCalibration(dir.string(), calibrated->rgb, calibrated->depth);

  poses_.clear();
  std::error_code ec;
  if (poses() != "none" && !poses().empty()) {
    const fs::path file = fs::path(poses()).is_absolute() ? fs::path(poses()) : dir / poses();
    if (fs::is_regular_file(file, ec)) {
      poses_ = parsePoseList(readTextFile(file.string()), file.string());
      if (poses_.size() != colour.size())
        throw ParseError(file.string(), 0,
                         "has " + std::to_string(poses_.size()) + " poses for " +
                             std::to_string(colour.size()) +
                             " colour images: the list holds one line per image, in number order");
    } else if (poses.isSet()) {
      throw InputError(describe() + ": no pose list '" + file.string() + "'");
    }
  }
  return pairs_.size();
}

std::optional<Eigen::Isometry3d> RgbdFolderSource::groundTruth(std::size_t i, double) const {
  if (poses_.empty()) return std::nullopt;
  return fromDataset(poses_[i]);
}

}  // namespace io
}  // namespace plugslam
