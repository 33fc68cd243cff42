#pragma once
// io.TrajectoryWriter: writes the run's final trajectory (TUM or KITTI) into the output folder.
#include <string>

#include "plugslam/sink.h"

namespace plugslam {
namespace io {

/// Writes RunResult::trajectory (or ::reference) atomically at the end of the run; an empty
/// trajectory is warned about, not written.
class TrajectoryWriter : public Sink {
 public:
  Param<std::string> file{this, "file", "", "",
                          "file name, relative to the run's output folder (empty: trajectory.tum "
                          "or trajectory.kitti, by format)"};
  Param<std::string> format{this,
                            "format",
                            "tum",
                            "",
                            "tum: t x y z qx qy qz qw; kitti: 3x4 rows",
                            Choices{{"tum", "kitti"}}};
  Param<std::string> trajectory{this,
                                "trajectory",
                                "estimate",
                                "",
                                "which trajectory: the run's estimate or the pipeline's reference "
                                "(ground truth, or the log's own poses)",
                                Choices{{"estimate", "reference"}}};
  Param<std::string> times_file{this, "times_file", "", "",
                                "kitti only: also write the timestamps to this file"};

  void configure() override;
  void begin(const std::string& out_dir) override;
  void end(const RunResult& result) override;

  /// Where the trajectory goes (after begin()): `file`, or trajectory.<format>.
  std::string outputPath() const;

 private:
  std::string resolve(const std::string& name) const;
  std::string out_dir_ = ".";
};

}  // namespace io
}  // namespace plugslam
