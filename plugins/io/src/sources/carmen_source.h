#pragma once
// io.CarmenSource: CARMEN logs (plain, gzip or bzip2) as a frame source, one frame per front-laser
// reading, with the wheel odometry and, for a corrected log, its corrected poses attached.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "readers/carmen_reader.h"
#include "sources/replay.h"

namespace plugslam {
namespace io {

/// Reads a CARMEN log into frames: raw[front] = LaserScan, raw[rear] = the latest rear scan
/// since the previous frame (if any), raw[odometry] = Odometry2D, raw[reference] = the robot
/// pose logged on the laser line when those poses are corrected ones (`laser_poses`).
///
/// Each frame keeps its laser line's ipc timestamp exactly, in file order; stamps earlier than
/// the previous scan's are reported (count and first line), never rewritten. Only a log without
/// times (0) gets synthesised stamps.
///
/// Odometry (use_laser_odometry = false) is the ODOM stream at the laser's time: the preceding
/// ODOM line when it carries the laser's timestamp (the GMapping-corrected logs) or the log has
/// no times, otherwise interpolated between the ODOM lines around the laser (time-ordered raw
/// logs). In GMapping-corrected logs the ODOM line right after each laser restarts dead reckoning
/// from the corrected pose; such restarts are detected (an ODOM pose equal to the preceding
/// laser's robot pose) and skipped, so the emitted odometry is one continuous dead-reckoned track
/// made of the logged increments.
class CarmenSource : public Source {
 public:
  Param<std::string> path{this, "path", "", "",
                          "CARMEN log to read (.clf/.log: plain text, gzip or bzip2)"};
  Output<LaserScan> front{this, Container::raw, "front", "front_laser",
                          "FLASER / ROBOTLASER1 scans (one frame each)"};
  Output<LaserScan> rear{this, Container::raw, "rear", "rear_laser",
                         "RLASER / ROBOTLASER2 scans (empty: not emitted)"};
  Output<Odometry2D> odometry{this, Container::raw, "odometry", "odom", "the wheel odometry"};
  Output<Eigen::Isometry2d> reference{
      this, Container::raw, "reference", "reference",
      "the robot pose logged on the laser line, when the poses are corrected ones "
      "(laser_poses)"};
  Param<std::string> on_error{this,
                              "on_error",
                              "strict",
                              "",
                              "malformed line: stop with an error, or warn and skip it",
                              Choices{{"strict", "skip"}}};
  Param<double> max_range{this,
                          "max_range",
                          0.0,
                          "m",
                          "maximum range of old-format scans; 0 = the log's PARAM or 80 m",
                          Range{0.0, 1000.0}};
  Param<std::string> laser_poses{
      this,
      "laser_poses",
      "auto",
      "",
      "what the laser lines' poses are: 'odometry' (a raw log: they are not a reference, none is "
      "written), 'corrected' (a mapper's output: written as the reference), 'auto': corrected "
      "when the log carries a corrector's trace (NEFF lines, or ODOM lines that restart dead "
      "reckoning at the laser lines' poses), odometry otherwise",
      Choices{{"auto", "odometry", "corrected"}}};
  Param<bool> use_laser_odometry{this, "use_laser_odometry", false, "",
                                 "take odometry from the laser line's robot pose instead of ODOM "
                                 "lines; a log without ODOM lines whose laser poses are odometry "
                                 "does so anyway (wrong for corrected logs)"};
  Param<double> max_odometry_gap{this,
                                 "max_odometry_gap",
                                 0.5,
                                 "s",
                                 "longest gap between ODOM lines to interpolate across",
                                 Range{0.0, 3600.0}};
  Param<double> fallback_period{this,
                                "fallback_period",
                                0.1,
                                "s",
                                "frame spacing used when the log has no timestamps",
                                Range{1e-6, 3600.0}};
  Param<int64_t> repeat{this,
                        "repeat",
                        1,
                        "",
                        "times to play the log (0: endlessly, until max_frames or Ctrl-C); "
                        "stamps keep increasing and the odometry stays one track across replays",
                        Range{0, 1e9}};

  CarmenSource();
  ~CarmenSource() override;

  void configure() override;
  bool next(Frame& frame) override;
  /// Number of front-laser lines (counted once by a light pass over the file) times `repeat`;
  /// -1 when replaying endlessly.
  int64_t sizeHint() const override;
  /// Replays started so far (1 during the first pass over the log).
  int64_t replay() const { return replay_.pass(); }

  /// Frames whose timestamp was missing (0) and was synthesised (in file order).
  std::size_t synthesizedStamps() const { return synthesized_stamps_; }
  /// Front-laser stamps (pass 1) earlier than the previous front laser's, kept as logged.
  std::size_t backwardStamps() const { return survey_.backward_stamps; }
  /// Front-laser stamps (pass 1) equal to the previous front laser's.
  std::size_t repeatedStamps() const { return survey_.repeated_stamps; }
  /// The laser poses are written as the reference (`laser_poses`, resolved on configure()).
  bool posesAreCorrected() const { return corrected_; }
  /// Odometry comes from the laser lines (`use_laser_odometry`, or a log without ODOM lines).
  bool odometryFromLaserLines() const { return laser_odometry_; }
  /// Odometry restarts detected and skipped (GMapping-corrected logs).
  std::size_t odometryRestarts() const { return restarts_; }
  /// Frames without an odometry entry because dead reckoning restarted at the previous laser and
  /// no ODOM line followed before this one (the motion between them is unknown).
  std::size_t unknownOdometryFrames() const { return unknown_odometry_frames_; }
  /// The reader's counters so far.
  const CarmenReaderStats& readerStats() const;

 private:
  // A front laser waiting for the next ODOM line (to interpolate the odometry at its time).
  struct Held {
    CarmenLaser laser;
    double stamp = 0;
    std::optional<LaserScan> rear;
    bool odometry_unknown = false;  // see odometry_unknown_
  };
  // What one light pass over the whole log tells before the first frame.
  struct Survey {
    int64_t front_lasers = 0;
    std::size_t odometry_lines = 0;
    std::size_t neff_lines = 0;    // a particle-filter mapper writes one per scan
    std::size_t restart_line = 0;  // first ODOM line jumping to a laser line's pose
    std::size_t backward_stamps = 0;
    std::size_t repeated_stamps = 0;
    std::size_t first_backward_line = 0;  // of backward or repeated ones
  };
  void open();
  // Reads the log once (size hint, which kind of log it is, stamp order) and says what it found.
  void survey();
  // A reader on path() whose warnings go through the skipped-line accounting below.
  void openReader();
  // Reopens the log for the next replay, keeping the odometry track and the clock going.
  void rewind();
  // Emits `held` with the odometry `odom`, read `age` seconds before the laser (empty: not
  // known, the log has no times).
  void fill(Frame& frame, Held& held, const std::optional<Eigen::Isometry2d>& odom,
            std::optional<double> age);
  // How long before `laser` the last ODOM reading was taken (empty: either has no time).
  std::optional<double> readingAge(const CarmenLaser& laser) const;
  void noteRecordStamp(double t);
  double maxRangeFor(const CarmenLaser& laser) const;
  LaserScan toScan(const CarmenLaser& laser) const;
  void onOdometry(const CarmenOdometry& odom);
  // Once, at the end of the log: what was skipped or flagged on the way.
  void summarize();

  std::unique_ptr<CarmenReader> reader_;
  mutable std::optional<int64_t> size_hint_;
  // Rear scan waiting for the next front frame.
  std::optional<LaserScan> pending_rear_;
  // Continuous odometry track built from ODOM increments.
  bool have_odom_ = false;
  Eigen::Isometry2d track_ = Eigen::Isometry2d::Identity();
  Eigen::Isometry2d last_raw_ = Eigen::Isometry2d::Identity();
  double last_odom_stamp_ = 0;
  bool last_odom_has_stamp_ = false;
  // The time of the last line that had one (an ODOM line without one is taken at it).
  double last_record_stamp_ = 0;
  bool have_record_stamp_ = false;
  // ODOM lines read so far, and the last one given to a frame with the stamp it was given.
  uint64_t reading_id_ = 0;
  uint64_t stamped_reading_ = UINT64_MAX;
  double stamped_at_ = 0;
  std::optional<Held> held_;
  std::optional<CarmenRecord> pushed_back_;
  // The robot pose of the most recent laser line, while no ODOM line has followed it.
  std::optional<CarmenPose> laser_before_odom_;
  // Dead reckoning restarted at a laser and no reading has followed yet: the motion since that
  // laser is unknown (a gap in the log), not zero, so the next laser gets no odometry entry.
  bool odometry_unknown_ = false;
  /// Frames given no odometry because the log has no ODOM reading since the previous laser.
  std::size_t unknown_odometry_frames_ = 0;
  // The latest front-laser stamp so far (a synthesised one continues from it) and the previous
  // front laser's log stamp.
  double last_stamp_ = 0;
  bool any_frame_ = false;
  Survey survey_;
  bool corrected_ = false;
  bool laser_odometry_ = false;
  std::size_t synthesized_stamps_ = 0;
  std::size_t restarts_ = 0;
  std::size_t skipped_seen_ = 0;  // malformed lines + empty scans + truncation already reported
  std::size_t skipped_warned_ = 0;
  bool summarized_ = false;
  // The pass over the log and the clock across passes.
  Replay replay_;
};

}  // namespace io
}  // namespace plugslam
