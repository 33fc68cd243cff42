#pragma once
// The ground-truth file a camera recording may ship beside its images (motion-capture or
// GNSS/INS poses, stamped on their own clock): which file to read, how far apart its rows may be,
// and the pose at a frame's time.
#include <spdlog/spdlog.h>

#include <filesystem>
#include <string>
#include <system_error>

#include "sources/camera_sequence_source.h"

namespace plugslam {
namespace io {

/// A camera sequence source (Base) whose ground truth is a file of timed rows, interpolated at
/// each frame's time.
template <class Base>
class WithGroundTruthFile : public Base {
 public:
  Param<std::string> ground_truth_file;
  Param<double> ground_truth_max_gap{
      this,
      "ground_truth_max_gap",
      0.05,
      "s",
      "longest gap between ground-truth rows to interpolate across (a 50 ms linear "
      "interpolation errs < 2 mm at 5 m/s^2)",
      Range{0.0, 10.0}};

 protected:
  /// `file_doc` says what ground_truth_file holds and which file it falls back to.
  explicit WithGroundTruthFile(const char* file_doc)
      : ground_truth_file{this, "ground_truth_file", "", "", file_doc} {}

  /// Reads ground_truth_file with `parse` (path -> Trajectory), or `fallback` when the
  /// parameter is empty and that file exists; "none" reads nothing.
  template <class Parse>
  void loadTruth(const std::filesystem::path& fallback, Parse parse) {
    truth_ = Trajectory();
    std::string gt = ground_truth_file();
    std::error_code ec;
    if (gt.empty() && std::filesystem::is_regular_file(fallback, ec)) gt = fallback.string();
    if (gt == "none") gt.clear();
    if (gt.empty()) return;
    truth_ = parse(gt);
    spdlog::info("{}: ground truth from '{}' ({} rows)", this->describe(), gt, truth_.size());
  }

  std::optional<Eigen::Isometry3d> groundTruth(std::size_t, double stamp) const override {
    return interpolatePose(truth_, stamp, ground_truth_max_gap());
  }

 private:
  Trajectory truth_;
};

}  // namespace io
}  // namespace plugslam
