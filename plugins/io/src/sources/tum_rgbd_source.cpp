#include "sources/tum_rgbd_source.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "plugslam/errors.h"
#include "readers/text_table.h"
#include "readers/tum_files.h"

namespace plugslam {
namespace io {
namespace fs = std::filesystem;

std::string TumRgbdSource::describe() const { return "TUM RGB-D sequence '" + path() + "'"; }

std::size_t TumRgbdSource::index() {
  const fs::path dir = folder();
  const std::string rgb_file = (dir / rgb_list()).string();
  const std::string depth_file = (dir / depth_list()).string();
  const auto colour = parseTumList(readTextFile(rgb_file), rgb_file);
  const auto depths = parseTumList(readTextFile(depth_file), depth_file);
  pairs_.clear();
  for (const TumPair& p : associateByTime(colour, depths, max_difference()))
    pairs_.push_back({colour[p.rgb].stamp, (dir / colour[p.rgb].file).string(),
                      (dir / depths[p.depth].file).string()});
  if (pairs_.empty())
    throw InputError(describe() + ": no colour image has a depth image within " +
                     std::to_string(max_difference()) + " s (" + std::to_string(colour.size()) +
                     " colour, " + std::to_string(depths.size()) + " depth)");
  if (pairs_.size() < colour.size())
    spdlog::info("{}: {} of {} colour images have a depth image within {} s", describe(),
                 pairs_.size(), colour.size(), max_difference());
  setCalibration(dir.string(), pairs_.front().rgb, pairs_.front().depth);

  loadTruth(dir / "groundtruth.txt", [](const std::string& gt) { return readTumTrajectory(gt); });
  return pairs_.size();
}

std::optional<Eigen::Isometry3d> TumRgbdSource::groundTruth(std::size_t i, double stamp) const {
  auto pose = WithGroundTruthFile::groundTruth(i, stamp);
  if (pose) return fromDataset(*pose);
  return std::nullopt;
}

}  // namespace io
}  // namespace plugslam
