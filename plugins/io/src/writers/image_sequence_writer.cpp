#include "writers/image_sequence_writer.h"

#include <filesystem>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {

ImageSequenceWriter::ImageSequenceWriter() = default;
ImageSequenceWriter::~ImageSequenceWriter() = default;

void ImageSequenceWriter::configure() {
  if (folder().empty()) throw ParamError("folder", "needs a folder name");
}

void ImageSequenceWriter::begin(const std::string& out_dir) {
  const std::filesystem::path f(folder());
  dir_ = f.is_absolute() ? f.string()
                         : (std::filesystem::path(out_dir.empty() ? "." : out_dir) / f).string();
  kitti_.reset();
  tum_.reset();
}

void ImageSequenceWriter::consume(const Frame& frame) {
  const Eigen::Isometry3d* pose = frame.raw.holds<Eigen::Isometry3d>(ground_truth())
                                      ? &frame.raw.get<Eigen::Isometry3d>(ground_truth())
                                      : nullptr;
  if (!pose)
    throw InputError("io.ImageSequenceWriter: frame has no Isometry3d raw entry '" +
                     ground_truth() + "' for the camera pose");
  if (layout() == "kitti") {
    const auto* left = frame.raw.find<Image>("left");
    const auto* right = frame.raw.find<Image>("right");
    const auto* camera = frame.raw.find<CameraInfo>("camera");
    if (!left || !right || !camera)
      throw InputError("io.ImageSequenceWriter: the kitti layout needs raw left, right and camera");
    if (!kitti_) kitti_ = std::make_unique<KittiWriter>(dir_, *camera);
    kitti_->add(frame.stamp, *left, *right, *pose);
  } else {
    const auto* rgb = frame.raw.find<Image>("rgb");
    const auto* depth = frame.raw.find<DepthImage>("depth");
    if (!rgb || !depth)
      throw InputError("io.ImageSequenceWriter: the tum layout needs raw rgb and depth");
    if (!tum_) tum_ = std::make_unique<TumWriter>(dir_);
    tum_->add(frame.stamp, *rgb, *depth, *pose);
  }
}

void ImageSequenceWriter::end(const RunResult&) {
  if (kitti_) kitti_->finish();
  if (tum_) tum_->finish();
}

}  // namespace io
}  // namespace plugslam
