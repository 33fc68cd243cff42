#pragma once
// io.ImageSequenceWriter: writes the run's raw images as a KITTI odometry (stereo) or TUM RGB-D
// sequence, so a simulated run can be replayed by the real-data readers.
#include <memory>
#include <string>

#include "plugslam/sink.h"
#include "writers/sequence_writers.h"

namespace plugslam {
namespace io {

/// Writes raw "left"/"right" (grey Image) as KITTI or raw "rgb"/"depth" as TUM RGB-D into a
/// folder of the run's output; poses from the raw ground truth (Eigen::Isometry3d).
class ImageSequenceWriter : public Sink {
 public:
  Param<std::string> layout{this,
                            "layout",
                            "tum",
                            "",
                            "kitti: image_0/, image_1/, calib.txt, times.txt, poses/00.txt; "
                            "tum: rgb/, depth/, rgb.txt, depth.txt, groundtruth.txt",
                            Choices{{"kitti", "tum"}}};
  Param<std::string> folder{this, "folder", "sequence", "",
                            "folder, relative to the run's output folder"};
  Param<std::string> ground_truth{this, "ground_truth", "ground_truth", "",
                                  "raw entry holding the camera pose (Isometry3d)"};

  ImageSequenceWriter();
  ~ImageSequenceWriter() override;

  void configure() override;
  void begin(const std::string& out_dir) override;
  void consume(const Frame& frame) override;
  void end(const RunResult& result) override;

 private:
  std::string dir_;
  std::unique_ptr<KittiWriter> kitti_;
  std::unique_ptr<TumWriter> tum_;
};

}  // namespace io
}  // namespace plugslam
