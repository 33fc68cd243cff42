#include "sources/camera_sequence_source.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <filesystem>
#include <set>

#include "plugslam/errors.h"
#include "images/image_file.h"

namespace plugslam {
namespace io {

CameraSequenceSource::~CameraSequenceSource() = default;

std::string CameraSequenceSource::folder() const {
  if (path().empty()) throw ParamError("path", "required: the dataset folder");
  std::error_code ec;
  if (!std::filesystem::is_directory(path(), ec))
    throw InputError("dataset folder '" + path() + "' " +
                     (std::filesystem::exists(path(), ec) ? "is not a folder" : "does not exist"));
  return path();
}

void CameraSequenceSource::readImage(const std::string& file, const std::string& entry,
                                     double stamp, int width, int height, Frame& frame) {
  Image im = readImageFile(file);
  if (im.width != width || im.height != height)
    throw InputError(file + ": image is " + std::to_string(im.width) + "x" +
                     std::to_string(im.height) + ", the calibration's is " +
                     std::to_string(width) + "x" + std::to_string(height));
  im.stamp = stamp;
  frame.raw.set<Image>(entry, std::move(im));
}

void CameraSequenceSource::checkEntries(
    std::initializer_list<const Param<std::string>*> entries) const {
  std::set<std::string> seen;
  std::vector<const Param<std::string>*> all(entries);
  all.push_back(&camera);
  if (!ground_truth().empty()) all.push_back(&ground_truth);
  for (const auto* p : all) {
    if (p->value().empty()) throw ParamError(p->name(), "must name a raw entry (not empty)");
    if (!seen.insert(p->value()).second)
      throw ParamError(p->name(), "raw entry '" + p->value() + "' is used twice");
  }
}

void CameraSequenceSource::configure() {
  calibration_ = CameraInfo{};
  count_ = index();
  next_ = 0;
  skipped_ = 0;
  summarized_ = false;
  configured_ = true;
  if (count_ == 0) throw InputError(describe() + " has no frames");
}

std::vector<ProvidedEntry> CameraSequenceSource::provides() const {
  std::vector<ProvidedEntry> out = imageEntries();
  out.push_back({camera(), typeid(CameraInfo)});
  if (!ground_truth().empty()) out.push_back({ground_truth(), typeid(Eigen::Isometry3d)});
  return out;
}

std::vector<ProvidedEntry> StereoSequenceSource::imageEntries() const {
  return {{left(), typeid(Image)}, {right(), typeid(Image)}};
}

void StereoSequenceSource::checkStereoEntries() const { checkEntries({&left, &right}); }

void StereoSequenceSource::readStereoPair(const std::string& left_file,
                                          const std::string& right_file, double stamp,
                                          Frame& frame) const {
  frame.stamp = stamp;
  readImage(left_file, left(), stamp, calibration_.width, calibration_.height, frame);
  const int w = calibration_.second ? calibration_.second->width : calibration_.width;
  const int h = calibration_.second ? calibration_.second->height : calibration_.height;
  readImage(right_file, right(), stamp, w, h, frame);
}

int64_t CameraSequenceSource::sizeHint() const {
  return configured_ ? static_cast<int64_t>(count_) : -1;
}

bool CameraSequenceSource::next(Frame& frame) {
  if (!configured_) configure();
  constexpr std::size_t kMaxWarnings = 5;
  while (next_ < count_) {
    const std::size_t i = next_++;
    try {
      read(i, frame);
    } catch (const InputError& e) {
      const std::string what =
          describe() + ", frame " + std::to_string(i) + " of " + std::to_string(count_) + ": " +
          e.what();
      if (on_error() != "skip") throw InputError(what);
      ++skipped_;
      if (skipped_ <= kMaxWarnings) {
        spdlog::warn("{}; frame skipped{}", what,
                     skipped_ == kMaxWarnings ? " (further skips at -v)" : "");
      } else {
        spdlog::debug("{}; frame skipped", what);
      }
      frame.raw.clear();
      continue;
    }
    frame.raw.set<CameraInfo>(camera(), calibration_);
    if (!ground_truth().empty()) {
      if (auto pose = groundTruth(i, frame.stamp))
        frame.raw.set<Eigen::Isometry3d>(ground_truth(), *pose);
    }
    return true;
  }
  if (!summarized_ && skipped_ > 0)
    spdlog::warn("{}: skipped {} of {} frames with bad files", describe(), skipped_, count_);
  summarized_ = true;
  return false;
}

std::vector<NumberedFile> listNumberedFiles(const std::string& dir, const std::string& extension) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw InputError("image folder '" + dir + "' does not exist");
  std::vector<NumberedFile> files;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= extension.size() ||
        name.compare(name.size() - extension.size(), extension.size(), extension) != 0)
      continue;
    const std::string stem = name.substr(0, name.size() - extension.size());
    if (stem.size() > 18 || stem.find_first_not_of("0123456789") != std::string::npos) continue;
    files.push_back({std::stoll(stem), name});
  }
  if (ec) throw InputError("cannot list image folder '" + dir + "': " + ec.message());
  if (files.empty())
    throw InputError("image folder '" + dir + "' holds no images named by a number (NNNNNN" +
                     extension + ")");
  std::sort(files.begin(), files.end(),
            [](const NumberedFile& a, const NumberedFile& b) { return a.number < b.number; });
  for (std::size_t i = 1; i < files.size(); ++i)
    if (files[i].number == files[i - 1].number)
      throw InputError("image folder '" + dir + "': '" + files[i - 1].name + "' and '" +
                       files[i].name + "' have the same number");
  return files;
}

std::optional<Eigen::Isometry3d> interpolatePose(const Trajectory& trajectory, double t,
                                                 double max_gap) {
  const auto& poses = trajectory.poses();
  if (poses.empty()) return std::nullopt;
  constexpr double kSame = 1e-6;
  auto after = std::lower_bound(poses.begin(), poses.end(), t,
                                [](const StampedPose& p, double x) { return p.t < x; });
  if (after != poses.end() && std::abs(after->t - t) <= kSame) return after->pose;
  if (after != poses.begin() && std::abs(std::prev(after)->t - t) <= kSame)
    return std::prev(after)->pose;
  if (after == poses.end() || after == poses.begin()) return std::nullopt;
  const StampedPose& a = *std::prev(after);
  const StampedPose& b = *after;
  if (b.t - a.t > max_gap) return std::nullopt;
  const double s = (t - a.t) / (b.t - a.t);
  const Eigen::Quaterniond qa(a.pose.rotation()), qb(b.pose.rotation());
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = qa.slerp(s, qb).toRotationMatrix();
  out.translation() = (1 - s) * a.pose.translation() + s * b.pose.translation();
  return out;
}

}  // namespace io
}  // namespace plugslam
