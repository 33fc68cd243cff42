#pragma once
// The part every camera dataset source shares: a sequence of frames indexed when configured and
// read one at a time, the strict / skip switch for a frame whose files are bad (as the CARMEN
// source has), and ground truth interpolated at the frame's time.
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "plugslam/trajectory.h"

namespace plugslam {
namespace io {

/// Base of the camera dataset sources (KITTI, KITTI raw, EuRoC, TUM RGB-D, RGB-D folders).
/// configure() indexes the dataset (index files, calibration: errors there always stop the run);
/// next() reads one frame; a missing, truncated or undecodable file of a frame, or one of the
/// wrong size, is an error naming the file and the frame (on_error: strict), or the frame is
/// skipped with a warning (skip) and a count at the end.
class CameraSequenceSource : public Source {
 public:
  Param<std::string> path{this, "path", "", "", "the dataset folder"};
  Param<std::string> on_error{this,
                              "on_error",
                              "strict",
                              "",
                              "a frame with a bad file: stop with an error, or warn and skip it",
                              Choices{{"strict", "skip"}}};
  Param<std::string> camera{this, "camera", "camera", "",
                            "raw entry for the calibration (CameraInfo)"};
  Param<std::string> ground_truth{this, "ground_truth", "ground_truth", "",
                                  "raw entry for the ground-truth pose (Isometry3d, the robot "
                                  "frame = parent of the camera mount, in the world)"};

  ~CameraSequenceSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// The frames indexed (skipped ones included), or -1 before configure().
  int64_t sizeHint() const override;
  /// Frames skipped so far (on_error: skip).
  std::size_t skippedFrames() const { return skipped_; }
  /// The calibration every frame carries (after configure()).
  const CameraInfo& calibration() const { return calibration_; }
  /// The raw entries of every frame: the images, the calibration and the ground truth (unless
  /// turned off; frames without a ground-truth row lack it).
  std::vector<ProvidedEntry> provides() const override;

 protected:
  /// Reads the dataset's index and calibration; sets calibration_ and returns the frame count.
  virtual std::size_t index() = 0;
  /// Fills frame i's stamp and raw images (not the calibration or ground truth); throws
  /// InputError naming the file on a bad one.
  virtual void read(std::size_t i, Frame& frame) = 0;
  /// The dataset's ground-truth pose at frame i, if it has one.
  virtual std::optional<Eigen::Isometry3d> groundTruth(std::size_t i, double stamp) const = 0;
  /// What the messages call the dataset ("KITTI sequence '...'").
  virtual std::string describe() const = 0;
  /// The image entries a frame carries, with their value types.
  virtual std::vector<ProvidedEntry> imageEntries() const = 0;

  /// Throws ParamError unless the raw entry names `entries`, camera and ground_truth are
  /// non-empty (ground_truth may be) and distinct.
  void checkEntries(std::initializer_list<const Param<std::string>*> entries) const;
  /// The folder `path` names, checked to exist (InputError naming it otherwise).
  std::string folder() const;
  /// Reads an image that must be width x height (InputError naming the file if not), stamped
  /// with `stamp`, into frame.raw[entry].
  static void readImage(const std::string& file, const std::string& entry, double stamp,
                        int width, int height, Frame& frame);

  CameraInfo calibration_;

 private:
  std::size_t count_ = 0;
  std::size_t next_ = 0;
  std::size_t skipped_ = 0;
  bool configured_ = false;
  bool summarized_ = false;
};

/// Base of the stereo layouts (KITTI, KITTI raw, EuRoC): the left and right image entries.
class StereoSequenceSource : public CameraSequenceSource {
 public:
  Param<std::string> left{this, "left", "left", "", "raw entry for the left image"};
  Param<std::string> right{this, "right", "right", "", "raw entry for the right image"};

 protected:
  std::vector<ProvidedEntry> imageEntries() const override;
  /// Throws ParamError unless the entries are named and distinct (checkEntries).
  void checkStereoEntries() const;
  /// Reads the pair into raw[left] and raw[right], each of its camera's size (the right one's is
  /// calibration_.second's when it has one), stamped `stamp`; frame.stamp = stamp.
  void readStereoPair(const std::string& left_file, const std::string& right_file, double stamp,
                      Frame& frame) const;
};

/// A file of a numbered image sequence ("000042.png" is number 42).
struct NumberedFile {
  int64_t number = 0;  ///< the number its name spells
  std::string name;    ///< the file name (no folder)
};

/// The files in `dir` named by digits alone plus `extension` (".png"), by number; InputError
/// naming the folder when it does not exist or holds none.
std::vector<NumberedFile> listNumberedFiles(const std::string& dir, const std::string& extension);

/// Ground truth sampled at arbitrary times: the pose at t, interpolated (linear in position,
/// slerp in rotation) between the two rows around t when they are at most max_gap apart; the
/// row itself when t is within 1 microsecond of one.
std::optional<Eigen::Isometry3d> interpolatePose(const Trajectory& trajectory, double t,
                                                 double max_gap);

}  // namespace io
}  // namespace plugslam
