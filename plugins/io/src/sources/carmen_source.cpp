#include "sources/carmen_source.h"

#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdlib>
#include <limits>

#include "plugslam/errors.h"
#include "plugslam/geometry.h"

namespace plugslam {
namespace io {
namespace {

Eigen::Isometry2d toIso(const CarmenPose& p) { return se2(p.x, p.y, p.theta); }

bool samePose(const CarmenPose& a, const CarmenPose& b) {
  // The restart line repeats the laser line's numbers verbatim, so they agree to print precision.
  return std::abs(a.x - b.x) < 1e-6 && std::abs(a.y - b.y) < 1e-6 &&
         std::abs(normalizeAngle(a.theta - b.theta)) < 1e-6;
}

bool isFront(const CarmenLaser& l) { return l.sensor == "front"; }
bool isRear(const CarmenLaser& l) { return l.sensor == "rear"; }

}  // namespace

CarmenSource::CarmenSource() = default;
CarmenSource::~CarmenSource() = default;

void CarmenSource::configure() {
  if (path().empty()) throw ParamError("path", "required: the CARMEN log to read");
  for (const EntryBase* e :
       {static_cast<const EntryBase*>(&front), static_cast<const EntryBase*>(&odometry),
        static_cast<const EntryBase*>(&reference)}) {
    if (e->name().empty()) throw ParamError(e->key(), "must name a raw entry (not empty)");
  }
  const std::string &f = front.name(), &r = rear.name(), &o = odometry.name(),
                    &g = reference.name();
  if (f == r || f == o || f == g || o == g || r == o || r == g) {
    throw ParamError("front", "front, rear, odometry and reference must be distinct entry names");
  }
  open();
}

void CarmenSource::open() {
  openReader();
  size_hint_.reset();
  survey();
  pending_rear_.reset();
  have_odom_ = false;
  laser_before_odom_.reset();
  odometry_unknown_ = false;
  unknown_odometry_frames_ = 0;
  last_odom_stamp_ = 0;
  last_odom_has_stamp_ = false;
  have_record_stamp_ = false;
  held_.reset();
  pushed_back_.reset();
  any_frame_ = false;
  synthesized_stamps_ = 0;
  restarts_ = 0;
  skipped_warned_ = 0;
  summarized_ = false;
  replay_.restart("CARMEN log '" + path() + "'");
}

void CarmenSource::survey() {
  survey_ = Survey{};
  CarmenReaderOptions options;
  options.policy = ErrorPolicy::kSkip;  // the real read reports malformed lines with their line
  options.time_policy = ErrorPolicy::kSkip;
  CarmenReader reader(path(), options);
  CarmenRecord record;
  // Plain flags rather than std::optional: GCC's -Wmaybe-uninitialized misreads the latter here.
  CarmenPose laser_pose, odom_pose;
  bool have_laser_pose = false, have_odom_pose = false;
  bool have_stamp = false;
  double previous = 0;
  while (reader.next(record)) {
    if (record.kind == CarmenRecord::Kind::kOdometry) {
      ++survey_.odometry_lines;
      const CarmenPose& pose = record.odometry.pose;
      // A corrector restarts dead reckoning at its corrected pose: the reading jumps to the
      // laser line's pose. A raw log's reading only equals it while the robot stands still.
      if (!survey_.restart_line && have_laser_pose && have_odom_pose &&
          samePose(laser_pose, pose) && !samePose(odom_pose, pose))
        survey_.restart_line = record.line;
      odom_pose = pose;
      have_odom_pose = true;
      have_laser_pose = false;
      continue;
    }
    if (record.kind != CarmenRecord::Kind::kLaser) continue;
    const CarmenLaser& laser = record.laser;
    if (laser.has_pose) {
      laser_pose = laser.robot_pose;
      have_laser_pose = true;
    }
    if (!isFront(laser)) continue;
    ++survey_.front_lasers;
    if (!laser.has_timestamp) continue;
    if (have_stamp && laser.timestamp <= previous) {
      ++(laser.timestamp < previous ? survey_.backward_stamps : survey_.repeated_stamps);
      if (!survey_.first_backward_line) survey_.first_backward_line = record.line;
    }
    previous = laser.timestamp;
    have_stamp = true;
  }
  const auto kinds = reader.stats().kinds;
  const auto neff = kinds.find("NEFF");
  survey_.neff_lines = neff == kinds.end() ? 0 : neff->second;
  size_hint_ = Replay::total(survey_.front_lasers, repeat());

  if (laser_poses() == "auto") {
    corrected_ = survey_.neff_lines > 0 || survey_.restart_line > 0;
    if (corrected_)
      spdlog::info(
          "CARMEN log '{}': its laser poses are taken as corrected ones and written as the "
          "reference ({}; source.laser_poses=odometry says otherwise)",
          path(),
          survey_.neff_lines > 0
              ? std::to_string(survey_.neff_lines) +
                    " NEFF lines, which a particle-filter mapper writes"
              : "line " + std::to_string(survey_.restart_line) +
                    " restarts dead reckoning at a laser line's pose, as a corrector writes it");
    else
      spdlog::info(
          "CARMEN log '{}': its laser poses are odometry (no corrector's trace in the log), so "
          "the run has no reference to score against; score the trajectory with `plugslam eval "
          "relations`, or set source.laser_poses=corrected if the poses are corrected ones",
          path());
  } else {
    corrected_ = laser_poses() == "corrected";
  }
  laser_odometry_ = use_laser_odometry() || (survey_.odometry_lines == 0 && !corrected_);
  if (laser_odometry_ && !use_laser_odometry())
    spdlog::info(
        "CARMEN log '{}' has no ODOM lines: odometry from its laser lines' odometry poses "
        "(FLASER/RLASER odom_x odom_y odom_theta, ROBOTLASER robot_pose)",
        path());
  if (survey_.backward_stamps + survey_.repeated_stamps > 0)
    spdlog::warn(
        "CARMEN log '{}': {} timestamp(s) went backwards (front-laser lines stamped earlier than "
        "the one before them) and {} repeated one, the first on line {}; kept as logged (frames "
        "come in file order, trajectories are written in time order{})",
        path(), survey_.backward_stamps, survey_.repeated_stamps, survey_.first_backward_line,
        survey_.repeated_stamps > 0 ? ", one pose per stamp" : "");
}

void CarmenSource::openReader() {
  CarmenReaderOptions options;
  options.policy = on_error() == "skip" ? ErrorPolicy::kSkip : ErrorPolicy::kStrict;
  // GMapping-corrected logs interleave timestamps out of order; that is not a malformed line.
  options.time_policy = ErrorPolicy::kSkip;
  if (max_range() > 0) options.old_format_max_range = max_range();
  // Every warning is logged at debug level (the corrected logs flag thousands of backwards
  // timestamps); skipped lines are also warned about (the first few) and everything is summed
  // up at the end of the log, so nothing is dropped silently.
  options.on_warning = [this](const ReaderWarning& w) {
    constexpr std::size_t kMaxWarnings = 5;
    const std::string text = w.file + ":" + std::to_string(w.line) + ": " + w.message;
    // The reader counts a skipped line before it warns about it.
    std::size_t skipped = skipped_seen_;
    if (reader_) {
      const CarmenReaderStats& s = reader_->stats();
      skipped = s.malformed + s.empty_scans + (s.truncated ? 1 : 0);
    }
    if (skipped != skipped_seen_ && skipped_warned_ < kMaxWarnings) {
      spdlog::warn("{}{}", text,
                   ++skipped_warned_ == kMaxWarnings ? " (further skipped lines at -v)" : "");
    } else {
      spdlog::debug("{}", text);
    }
    skipped_seen_ = skipped;
  };
  skipped_seen_ = 0;
  reader_ = std::make_unique<CarmenReader>(path(), options);
}

void CarmenSource::rewind() {
  // The reader and the per-pass line state start over; the odometry track, the last stamp and
  // the counters of what was synthesised carry on, so the replay looks like the robot jumping
  // back to its start pose (the odometry increment from the log's last reading to its first)
  // at a later time. Skipped-line warnings are given for the first pass only.
  openReader();
  pending_rear_.reset();
  laser_before_odom_.reset();
  odometry_unknown_ = false;
  last_odom_stamp_ = 0;
  last_odom_has_stamp_ = false;
  have_record_stamp_ = false;
  held_.reset();
  pushed_back_.reset();
}

void CarmenSource::summarize() {
  if (summarized_) return;
  summarized_ = true;
  const CarmenReaderStats& s = reader_->stats();
  if (s.malformed || s.empty_scans || s.truncated) {
    spdlog::warn(
        "CARMEN log '{}': skipped {} malformed line(s) and {} empty scan(s){}; {} "
        "timestamp(s) went backwards",
        path(), s.malformed, s.empty_scans,
        s.truncated ? ", the compressed stream is truncated" : "", s.time_backwards);
  } else if (s.time_backwards) {
    // The front laser's were reported before the first frame (survey()); these count every
    // stream's, ODOM lines' too.
    spdlog::debug("CARMEN log '{}': {} timestamp(s) went backwards (flagged, kept in file order)",
                  path(), s.time_backwards);
  }
}

const CarmenReaderStats& CarmenSource::readerStats() const {
  static const CarmenReaderStats kEmpty;
  return reader_ ? reader_->stats() : kEmpty;
}

int64_t CarmenSource::sizeHint() const {
  if (size_hint_) return *size_hint_;
  if (path().empty()) return -1;
  try {
    CarmenReaderOptions options;
    options.policy = ErrorPolicy::kSkip;
    options.time_policy = ErrorPolicy::kSkip;
    CarmenReader counter(path(), options);
    CarmenRecord record;
    int64_t n = 0;
    while (counter.next(record)) {
      if (record.kind == CarmenRecord::Kind::kLaser && isFront(record.laser)) ++n;
    }
    size_hint_ = Replay::total(n, repeat());
  } catch (const Error&) {
    size_hint_ = -1;  // the real read reports the problem with its line number
  }
  return *size_hint_;
}

double CarmenSource::maxRangeFor(const CarmenLaser& laser) const {
  const bool old_format = laser.message == "FLASER" || laser.message == "RLASER";
  if (!old_format || max_range() > 0) return laser.max_range;
  // Old formats do not log the range limit; CARMEN keeps it in a PARAM line.
  const auto& params = reader_->params();
  auto it =
      params.find(laser.message == "FLASER" ? "robot_front_laser_max" : "robot_rear_laser_max");
  if (it != params.end()) {
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end != it->second.c_str() && std::isfinite(v) && v > 0) return v;
  }
  return laser.max_range;
}

LaserScan CarmenSource::toScan(const CarmenLaser& laser) const {
  LaserScan scan;
  scan.stamp = laser.timestamp;
  scan.angle_min = laser.angle_min;
  scan.angle_increment = laser.angle_increment;
  scan.range_min = 0.0;
  scan.range_max = maxRangeFor(laser);
  scan.ranges = laser.ranges;
  if (laser.message == "FLASER") {
    scan.mount = se2(laser.forward_offset, 0.0, 0.0);
  } else if (laser.message == "RLASER") {
    // CARMEN's rear laser sits on the robot's x axis looking backwards.
    scan.mount = se2(laser.forward_offset, 0.0, M_PI);
  } else if (laser.has_pose) {
    scan.mount = toIso(laser.robot_pose).inverse() * toIso(laser.laser_pose);
  }
  return scan;
}

void CarmenSource::onOdometry(const CarmenOdometry& odom) {
  const Eigen::Isometry2d raw = toIso(odom.pose);
  // Only a corrector restarts dead reckoning; in a raw log a reading equal to the laser line's
  // pose is a robot standing still, whose (zero) motion is known.
  if (corrected_ && laser_before_odom_ && samePose(*laser_before_odom_, odom.pose)) {
    // Dead reckoning restarted from the corrected pose: no motion happened here.
    last_raw_ = raw;
    ++restarts_;
    odometry_unknown_ = true;
  } else if (!have_odom_) {
    track_ = raw;
    last_raw_ = raw;
    have_odom_ = true;
    odometry_unknown_ = false;
  } else {
    track_ = track_ * (last_raw_.inverse() * raw);
    last_raw_ = raw;
    odometry_unknown_ = false;
  }
  laser_before_odom_.reset();
  ++reading_id_;
  // A line without a time (GMapping-corrected logs write 0 on their restart lines) was logged
  // after the last line with one: it is taken at that time, so the age of the reading a later
  // laser gets is still known (never shorter than the truth).
  last_odom_stamp_ = odom.has_timestamp ? odom.timestamp : last_record_stamp_;
  last_odom_has_stamp_ = odom.has_timestamp || have_record_stamp_;
  if (odom.has_timestamp) noteRecordStamp(odom.timestamp);
}

void CarmenSource::noteRecordStamp(double t) {
  if (!std::isfinite(t)) return;
  last_record_stamp_ = t;
  have_record_stamp_ = true;
}

std::optional<double> CarmenSource::readingAge(const CarmenLaser& laser) const {
  if (!laser.has_timestamp || !std::isfinite(laser.timestamp) || !last_odom_has_stamp_)
    return std::nullopt;
  return std::max(0.0, laser.timestamp - last_odom_stamp_);
}

void CarmenSource::fill(Frame& frame, Held& held, const std::optional<Eigen::Isometry2d>& odom,
                        std::optional<double> age) {
  const CarmenLaser& laser = held.laser;
  frame.stamp = held.stamp;
  LaserScan scan = toScan(laser);
  scan.stamp = held.stamp;
  front.set(frame, std::move(scan));
  if (held.rear && !rear.name().empty()) rear.set(frame, std::move(*held.rear));
  if (laser_odometry_) {
    if (laser.has_pose) {
      odometry.set(frame, {held.stamp, toIso(laser.robot_pose)});
    }
  } else if (held.odometry_unknown) {
    // Leaving the entry out lets the motion model and the prior span the gap from the last
    // reading (the track did not move during it) instead of asserting zero motion.
    ++unknown_odometry_frames_;
    spdlog::debug(
        "CARMEN log '{}': no ODOM reading between the laser lines at t = {} and the one "
        "before; frame without odometry",
        path(), held.stamp);
  } else if (odom) {
    // The reading's own time, on the frame's clock: a laser logged after the last ODOM line
    // gets that reading, which says nothing about the motion since (the motion model
    // extrapolates it). Without times, a reading given to a second frame keeps the stamp of the
    // first one it was given to.
    double stamp = held.stamp;
    if (age)
      stamp = held.stamp - *age;
    else if (reading_id_ == stamped_reading_)
      stamp = stamped_at_;
    if (reading_id_ != stamped_reading_) {
      stamped_reading_ = reading_id_;
      stamped_at_ = stamp;
    }
    odometry.set(frame, {stamp, *odom});
  }
  // The reference is the robot's pose: the logged laser pose moved back by the mount. In raw
  // logs that is the logged robot pose; GMapping-corrected logs write GMapping's estimate of the
  // laser pose into both fields (scans placed at it as the laser pose make a crisper map than at
  // it as the robot pose on every log with a laser offset), so the robot field would be off by
  // the offset, turned with the robot.
  if (corrected_ && laser.has_pose) {
    const LaserScan& placed = frame.raw.get<LaserScan>(front.name());
    reference.set(frame, toIso(laser.laser_pose) * placed.mount.inverse());
  }
}

bool CarmenSource::next(Frame& frame) {
  if (!reader_) open();
  CarmenRecord record;
  for (;;) {
    if (pushed_back_) {
      record = std::move(*pushed_back_);
      pushed_back_.reset();
    } else if (!reader_->next(record)) {
      summarize();
      if (!held_ && !any_frame_) {
        throw InputError(
            "CARMEN log '" + path() + "' has no front-laser line (FLASER or ROBOTLASER1); " +
            std::to_string(reader_->stats().lasers) + " other laser lines, " +
            std::to_string(reader_->stats().odometry) + " ODOM lines" +
            (reader_->stats().empty_scans
                 ? ", " + std::to_string(reader_->stats().empty_scans) + " empty scans (skipped)"
                 : std::string()));
      }
      if (!held_) {
        if (!replay_.next(repeat(), fallback_period())) return false;
        rewind();
        continue;
      }
      fill(frame, *held_, have_odom_ ? std::optional<Eigen::Isometry2d>(track_) : std::nullopt,
           readingAge(held_->laser));
      held_.reset();
      return true;
    }

    if (record.kind == CarmenRecord::Kind::kOdometry) {
      const Eigen::Isometry2d before = track_;
      const double t0 = last_odom_stamp_;
      const std::size_t restarts = restarts_;
      onOdometry(record.odometry);
      if (!held_) continue;
      // The reading after a held laser: interpolate between the two around the laser's time,
      // unless this line restarted dead reckoning or the gap is too long to trust.
      std::optional<Eigen::Isometry2d> odom = before;
      std::optional<double> age = std::max(0.0, held_->laser.timestamp - t0);  // `before`'s
      const double t1 = record.odometry.timestamp;
      if (restarts_ == restarts && record.odometry.has_timestamp && t1 > held_->laser.timestamp &&
          t1 - t0 <= max_odometry_gap()) {
        const double alpha = (held_->laser.timestamp - t0) / (t1 - t0);
        odom = before * se2(alpha * toVector(before.inverse() * track_));
        age = 0.0;
      }
      fill(frame, *held_, odom, age);
      held_.reset();
      return true;
    }
    if (record.kind != CarmenRecord::Kind::kLaser) continue;
    const CarmenLaser& laser = record.laser;
    if (isRear(laser)) {
      if (laser.has_pose) laser_before_odom_ = laser.robot_pose;
      if (laser.has_timestamp) noteRecordStamp(laser.timestamp);
      pending_rear_ = toScan(laser);
      continue;
    }
    if (!isFront(laser)) continue;
    if (held_) {
      // Another laser before any further odometry: the held one keeps the preceding reading.
      pushed_back_ = std::move(record);
      fill(frame, *held_, have_odom_ ? std::optional<Eigen::Isometry2d>(track_) : std::nullopt,
           readingAge(held_->laser));
      held_.reset();
      return true;
    }
    if (laser.has_pose) laser_before_odom_ = laser.robot_pose;
    if (laser.has_timestamp) noteRecordStamp(laser.timestamp);

    Held held;
    held.stamp = laser.timestamp;
    if (laser.has_timestamp && std::isfinite(laser.timestamp)) {
      // A replay continues the clock one frame period after the previous pass.
      replay_.anchor(laser.timestamp);
      held.stamp = replay_.shift(laser.timestamp);
    }
    if (!laser.has_timestamp || !std::isfinite(held.stamp)) {
      // No time at all (some logs write 0): keep the file's order. A stamp that goes backwards
      // is kept as logged (survey() reports them): evaluation matches scans by their stamps.
      held.stamp = any_frame_ ? last_stamp_ + fallback_period() : 0.0;
      ++synthesized_stamps_;
    }
    last_stamp_ = any_frame_ ? std::max(last_stamp_, held.stamp) : held.stamp;
    any_frame_ = true;
    // A later pass starts after the latest stamp, not after the last line's.
    replay_.frame(last_stamp_);
    held.rear = std::move(pending_rear_);
    pending_rear_.reset();
    held.laser = laser;
    held.odometry_unknown = !laser_odometry_ && odometry_unknown_;

    // The preceding ODOM line is the reading at the laser when it carries the laser's time (the
    // GMapping-corrected logs) or when the log has no times; a laser logged after the last
    // reading waits for the next one to interpolate.
    const bool wait = !laser_odometry_ && have_odom_ && laser.has_timestamp &&
                      last_odom_has_stamp_ && laser.timestamp > last_odom_stamp_ + 1e-9 &&
                      laser.timestamp - last_odom_stamp_ <= max_odometry_gap();
    if (wait) {
      held_ = std::move(held);
      continue;
    }
    fill(frame, held, have_odom_ ? std::optional<Eigen::Isometry2d>(track_) : std::nullopt,
         readingAge(laser));
    return true;
  }
}

}  // namespace io
}  // namespace plugslam
