#include "sources/rgbd_folder_source.h"

#include <spdlog/spdlog.h>

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
  pairs_.clear();
  std::size_t lonely = 0;
  for (const auto& f : colour) {
    auto it = depth.find(f.number);
    if (it == depth.end()) {
      ++lonely;
      continue;
    }
    pairs_.push_back({(cdir / f.name).string(), (ddir / it->second).string()});
  }
  if (pairs_.empty())
    throw InputError(describe() + ": no colour image in '" + cdir.string() +
                     "' has a depth image of the same number in '" + ddir.string() + "'");
  if (lonely > 0)
    spdlog::warn("{}: {} colour image(s) without a depth image of the same number (not used)",
                 describe(), lonely);
  setCalibration(dir.string(), pairs_.front().rgb, pairs_.front().depth);

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
      // Keep the poses of the frames that have depth, in the same order.
      std::vector<Eigen::Isometry3d> kept;
      for (std::size_t k = 0; k < colour.size(); ++k)
        if (depth.count(colour[k].number)) kept.push_back(poses_[k]);
      poses_ = std::move(kept);
    } else if (poses.isSet()) {
      throw InputError(describe() + ": no pose list '" + file.string() + "'");
    }
  }
  return pairs_.size();
}

void RgbdFolderSource::read(std::size_t i, Frame& frame) {
  const double stamp = static_cast<double>(i) / rate();
  frame.stamp = stamp;
  readPair(pairs_[i].rgb, pairs_[i].depth, stamp, frame);
}

std::optional<Eigen::Isometry3d> RgbdFolderSource::groundTruth(std::size_t i, double) const {
  if (poses_.empty()) return std::nullopt;
  return fromDataset(poses_[i]);
}

}  // namespace io
}  // namespace plugslam
