#include "intel_run.h"

#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "occupancy_map_writer.h"
#include "plugslam/errors.h"
#include "plugslam/multi_tracker.h"
#include "plugslam/pipeline.h"
#include "plugslam/registry.h"
#include "point_map_slice.h"
#include "readers/carmen_reader.h"
#include "scan_preprocessor.h"
#include "scan_slices.h"

namespace plugslam::laser2d::test {

namespace {

SE2 poseOf(const io::CarmenPose& p) { return se2(p.x, p.y, p.theta); }

// Motion prediction from the odometry increment each frame carries (raw entry "odom_delta"),
// with odometry.WheelOdometry's default noise model (a differential drive's: a few per cent of
// the step, a fifth of a turn in heading, above floors).
class DeltaMotion final : public MotionModel<Space2D> {
 public:
  std::optional<MotionEstimate<Space2D>> predict(const Frame& frame) override {
    const SE2* d = frame.raw.find<SE2>("odom_delta");
    if (!d) return std::nullopt;
    const double m = d->translation().norm();
    const double a = std::abs(std::atan2((*d)(1, 0), (*d)(0, 0)));
    const double st = std::max(0.02, 0.02 * m + 0.05 * a);
    const double sr = std::max(0.05, 0.02 * m + 0.2 * a);
    return MotionEstimate<Space2D>::isotropic(*d, st, sr);
  }
};

struct LogScan {
  LaserScan scan;
  SE2 logged;     // the pose on the laser line
  SE2 reference;  // the robot's pose
  std::optional<SE2> odom_delta;
};

std::vector<LogScan> readLog(const std::string& path) {
  io::CarmenReaderOptions options;
  options.time_policy = io::ErrorPolicy::kSkip;
  io::CarmenReader reader(path, options);
  io::CarmenRecord record;
  std::vector<LogScan> scans;
  // The last ODOM pose since the previous scan (GCC warns on std::optional of an Eigen type).
  SE2 last_odom = SE2::Identity();
  bool have_odom = false;
  while (reader.next(record)) {
    if (record.kind == io::CarmenRecord::Kind::kOdometry) {
      last_odom = poseOf(record.odometry.pose);
      have_odom = true;
      continue;
    }
    if (record.kind != io::CarmenRecord::Kind::kLaser || record.laser.sensor != "front") continue;
    const auto& l = record.laser;
    LogScan s;
    s.scan.stamp = static_cast<double>(scans.size());
    s.scan.angle_min = l.angle_min;
    s.scan.angle_increment = l.angle_increment;
    s.scan.range_min = 0.0;
    s.scan.range_max = l.max_range;
    s.scan.ranges = l.ranges;
    s.scan.mount = se2(l.forward_offset, 0.0, 0.0);
    // The logged pose is the laser's (as io.CarmenSource reads it): the robot is one mount back.
    s.logged = poseOf(l.laser_pose);
    s.reference = s.logged * s.scan.mount.inverse();
    // In the corrected logs odometry restarts from each logged scan pose: the increment is the
    // last ODOM pose before this scan, seen from the previous scan's logged pose.
    if (!scans.empty() && have_odom) s.odom_delta = scans.back().logged.inverse() * last_odom;
    have_odom = false;
    scans.push_back(std::move(s));
  }
  return scans;
}

void applyOverrides(const FrontendOptions& options,
                    const std::vector<std::pair<std::string, Configurable*>>& modules) {
  for (const auto& [key, value] : options.overrides) {
    const auto dot = key.find('.');
    bool done = false;
    for (const auto& [name, module] : modules) {
      if (dot == std::string::npos || key.substr(0, dot) != name) continue;
      ParamBase* param = module->findParam(key.substr(dot + 1));
      if (!param) throw InputError("unknown parameter " + key);
      param->fromYaml(YAML::Load(value));
      done = true;
    }
    if (!done) throw InputError("unknown module in " + key);
  }
}

}  // namespace

FrontendRun runFrontend(const std::string& log, const FrontendOptions& options) {
  const std::vector<LogScan> scans = readLog(log);
  FrontendRun out;
  out.scans = scans.size();
  if (!scans.empty()) out.beams = scans.front().scan.ranges.size();
  out.seconds = std::numeric_limits<double>::infinity();
  for (int run = 0; run < std::max(1, options.repeat); ++run) {
    ScanPreprocessor pre;
    pre.input = "front_laser";
    pre.output = "front";
    pre.configure();
    MultiTracker<Space2D> tracker;
    auto aligner = std::make_shared<MultiAligner<Space2D>>();
    auto slice = std::make_shared<PointToLineSlice>();
    slice->association = options.association;
    slice->configure();
    aligner->slices.assign(slice);
    tracker.aligner.assign(aligner);
    tracker.slices.assign(std::make_shared<PointMapSlice>());
    auto splitter = std::make_shared<DistanceSplitter>();
    splitter->distance = options.split_distance;
    tracker.splitter.assign(splitter);
    if (options.odometry) tracker.motion.assign(std::make_shared<DeltaMotion>());
    applyOverrides(options, {{"preprocessor", &pre},
                             {"slice", slice.get()},
                             {"map", &*tracker.slices.begin()->get()},
                             {"aligner", aligner.get()},
                             {"splitter", splitter.get()}});
    pre.configure();
    slice->configure();
    tracker.configure();
    Pipeline pipeline;  // places the local maps and composes the world pose, as a run does
    pipeline.tracker.assign(std::shared_ptr<Tracker>(std::shared_ptr<Tracker>(), &tracker));

    // Frames are prepared outside the timed loop: the source is not the front-end.
    std::vector<Frame> frames(scans.size());
    for (size_t i = 0; i < scans.size(); ++i) {
      frames[i].seq = i;
      frames[i].stamp = scans[i].scan.stamp;
      frames[i].raw.set("front_laser", scans[i].scan);
      if (scans[i].odom_delta) frames[i].raw.set("odom_delta", *scans[i].odom_delta);
    }
    const auto start = std::chrono::steady_clock::now();
    for (auto& frame : frames) {
      pre.process(frame);
      pipeline.process(frame);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (seconds < out.seconds) out.seconds = seconds;

    out.estimate = Trajectory();
    out.reference = Trajectory();
    for (size_t i = 0; i < frames.size(); ++i) {
      out.estimate.push_back(frames[i].stamp, frames[i].estimate.world);
      out.reference.push_back(frames[i].stamp, Space2D::to3D(scans[i].reference));
    }
    if (!options.map_dir.empty() && run + 1 == std::max(1, options.repeat)) {
      OccupancyMapWriter writer;
      writer.max_range = 25.0;
      writer.begin(options.map_dir);
      for (const auto& frame : frames) writer.consume(frame);
      RunResult result;
      result.trajectory = out.estimate;
      writer.end(result);
    }
    out.aligned = tracker.stats().aligned;
    out.local_maps = tracker.stats().local_maps;
    out.mean_inlier_ratio =
        out.aligned ? tracker.stats().inlier_ratio_sum / static_cast<double>(out.aligned) : 0.0;
  }
  out.scans_per_second = out.seconds > 0 ? out.scans / out.seconds : 0.0;
  return out;
}

RpeResult relativeError(const FrontendRun& run, double meters) {
  RpeOptions options;
  options.unit = RpeUnit::Meters;
  options.delta = meters;
  options.association.max_time_diff = 1e-6;
  return computeRpe(run.reference, run.estimate, options);
}

}  // namespace plugslam::laser2d::test
