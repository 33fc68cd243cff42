#include "writers/trajectory_writer.h"

#include <filesystem>

#include <spdlog/spdlog.h>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {

void TrajectoryWriter::configure() {
  if (!times_file().empty() && format() != "kitti") {
    throw ParamError("times_file", "only the kitti format keeps timestamps apart");
  }
}

void TrajectoryWriter::begin(const std::string& out_dir) {
  out_dir_ = out_dir.empty() ? "." : out_dir;
}

std::string TrajectoryWriter::resolve(const std::string& name) const {
  std::filesystem::path p(name);
  if (p.is_absolute()) return p.string();
  return (std::filesystem::path(out_dir_) / p).string();
}

std::string TrajectoryWriter::outputPath() const {
  return resolve(file().empty() ? "trajectory." + format() : file());
}

void TrajectoryWriter::end(const RunResult& result) {
  const Trajectory& t = trajectory() == "reference" ? result.reference : result.trajectory;
  if (t.empty()) {
    // An empty file would read as a run that estimated nothing without saying why.
    const bool stale = std::filesystem::exists(outputPath());
    spdlog::warn("{}: no {} to write ({}); {} not written{}", name(),
                 trajectory() == "reference" ? "reference poses" : "poses",
                 trajectory() == "reference" ? "the source gives no reference"
                                             : "the pipeline estimated none: has it a tracker?",
                 outputPath(), stale ? " (the file there is from an earlier run)" : "");
    return;
  }
  if (format() == "kitti") {
    writeKittiTrajectory(t, outputPath(), times_file().empty() ? std::string() : resolve(times_file()));
  } else {
    writeTumTrajectory(t, outputPath());
  }
}

}  // namespace io
}  // namespace plugslam
