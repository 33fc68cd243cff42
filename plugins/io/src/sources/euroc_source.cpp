#include "sources/euroc_source.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "plugslam/errors.h"
#include "readers/euroc_files.h"
#include "readers/text_table.h"

namespace plugslam {
namespace io {
namespace fs = std::filesystem;

std::string EurocSource::describe() const { return "EuRoC sequence '" + path() + "'"; }

std::size_t EurocSource::index() {
  checkStereoEntries();
  if (left_camera() == right_camera())
    throw ParamError("right_camera", "must differ from left_camera");
  std::error_code ec;
  fs::path mav = fs::path(folder()) / "mav0";
  if (!fs::is_directory(mav, ec)) mav = fs::path(folder());  // the mav0 folder itself
  const auto camFile = [&](const std::string& cam, const char* name) {
    return (mav / cam / name).string();
  };
  for (const std::string& cam : {left_camera(), right_camera()})
    if (!fs::is_directory(mav / cam, ec))
      throw InputError(describe() + ": no camera folder '" + (mav / cam).string() +
                       "' (expected the EuRoC layout mav0/" + cam + "/)");

  const EurocCamera cam0 =
      parseEurocSensor(readTextFile(camFile(left_camera(), "sensor.yaml")),
                       camFile(left_camera(), "sensor.yaml"));
  const EurocCamera cam1 =
      parseEurocSensor(readTextFile(camFile(right_camera(), "sensor.yaml")),
                       camFile(right_camera(), "sensor.yaml"));
  calibration_.setIntrinsics(cam0.intrinsics);
  calibration_.baseline = 0;  // raw images: the pair is rectified downstream
  calibration_.mount = cam0.T_BS;
  calibration_.second = cam1.intrinsics;
  calibration_.second_pose = cam0.T_BS.inverse() * cam1.T_BS;

  const auto list0 = parseEurocImageList(readTextFile(camFile(left_camera(), "data.csv")),
                                         camFile(left_camera(), "data.csv"));
  const auto list1 = parseEurocImageList(readTextFile(camFile(right_camera(), "data.csv")),
                                         camFile(right_camera(), "data.csv"));
  // The VI-sensor triggers both cameras together: a pair shares its timestamp exactly.
  pairs_.clear();
  std::size_t j = 0, unpaired = 0;
  for (const EurocImage& a : list0) {
    while (j < list1.size() && list1[j].stamp_ns < a.stamp_ns) ++j, ++unpaired;
    if (j < list1.size() && list1[j].stamp_ns == a.stamp_ns) {
      pairs_.push_back({a.stamp_ns, (mav / left_camera() / "data" / a.file).string(),
                        (mav / right_camera() / "data" / list1[j].file).string()});
      ++j;
    } else {
      ++unpaired;
    }
  }
  unpaired += list1.size() - j;
  if (unpaired > 0)
    spdlog::warn("{}: {} image(s) without a partner at the same timestamp in the other camera "
                 "(not used)",
                 describe(), unpaired);

  loadTruth(mav / "state_groundtruth_estimate0" / "data.csv",
            [](const std::string& gt) { return parseEurocGroundTruth(readTextFile(gt), gt); });
  spdlog::info("{}: {} raw stereo pairs ({}x{}, {} distortion, cameras {:.4f} m apart)",
               describe(), pairs_.size(), calibration_.width, calibration_.height,
               distortionModelName(calibration_.distortion.model),
               calibration_.second_pose.translation().norm());
  return pairs_.size();
}

void EurocSource::read(std::size_t i, Frame& frame) {
  const Pair& p = pairs_[i];
  readStereoPair(p.left, p.right, static_cast<double>(p.stamp_ns) * 1e-9, frame);
}

}  // namespace io
}  // namespace plugslam
