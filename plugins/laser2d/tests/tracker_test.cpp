// A MultiTracker2D built in code with the laser2d modules recovers a synthetic trajectory, with
// motion predicted from biased odometry increments.
#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <utility>

#include "plugslam/multi_tracker.h"
#include "plugslam/pipeline.h"
#include "point_map_slice.h"
#include "scan_preprocessor.h"
#include "scan_slices.h"
#include "synthetic.h"

namespace plugslam::laser2d {
namespace {

std::vector<test::Segment> office() {
  std::vector<test::Segment> w = test::box(0, 0, 14, 9);
  for (const auto& b : {test::box(3, 3, 4, 4), test::box(8, 5.5, 9.5, 6),
                        test::box(11, 2, 11.5, 3.5), test::box(5.5, 7, 6, 9)})
    w.insert(w.end(), b.begin(), b.end());
  return w;
}

// Motion prediction from the increment the frame carries (biased odometry, built below), with
// the standard deviations (m, rad) the frame's raw "odom_sigma" says, else 5 cm and 0.05 rad.
class OdometryIncrement final : public MotionModel<Space2D> {
 public:
  std::optional<MotionEstimate<Space2D>> predict(const Frame& frame) override {
    const SE2* d = frame.raw.find<SE2>("odom_delta");
    if (!d) return std::nullopt;
    const Eigen::Vector2d* sigma = frame.raw.find<Eigen::Vector2d>("odom_sigma");
    const Eigen::Vector2d s = sigma ? *sigma : Eigen::Vector2d(0.05, 0.05);
    return MotionEstimate<Space2D>::isotropic(*d, s.x(), s.y());
  }
};

// A lap around the room: straight legs and turns, 0.15 m and up to ~0.15 rad per frame.
std::vector<SE2> lap() {
  std::vector<SE2> poses;
  SE2 t = se2(1.5, 1.5, 0.0);
  auto go = [&](int steps, double step, double turn) {
    for (int i = 0; i < steps; ++i) {
      t = t * se2(step, 0.0, turn);
      poses.push_back(t);
    }
  };
  poses.push_back(t);
  go(55, 0.15, 0.0);
  go(10, 0.05, M_PI / 20);
  go(30, 0.15, 0.0);
  go(10, 0.05, M_PI / 20);
  go(55, 0.15, 0.0);
  go(10, 0.05, M_PI / 20);
  go(25, 0.15, 0.0);
  return poses;
}

// Tracks the lap around the office with odometry increments odometry(k, true increment) and
// returns the worst world-pose error over it (m, rad).
std::pair<double, double> trackLap(
    MultiTracker<Space2D>& tracker,
    const std::function<SE2(size_t, const Eigen::Vector3d&)>& odometry,
    const std::vector<SE2>& truth = lap(), double interval = 0.1,
    const std::function<std::optional<Eigen::Vector2d>(size_t)>& sigma = {}) {
  Pipeline pipeline;  // places the local maps and composes the world pose
  pipeline.tracker.assign(std::shared_ptr<Tracker>(std::shared_ptr<Tracker>(), &tracker));
  ScanPreprocessor pre;
  pre.configure();
  const auto world = office();
  test::ScanSpec spec;
  spec.beams = 180;
  spec.fov = M_PI;
  spec.noise = 0.01;
  double worst = 0, worst_angle = 0;
  for (size_t k = 0; k < truth.size(); ++k) {
    spec.seed = static_cast<uint32_t>(k + 1);
    Frame frame;
    frame.seq = k;
    frame.stamp = interval * k;
    frame.raw.set("front_laser", test::castScan(world, truth[k], spec));
    if (k > 0)
      frame.raw.set("odom_delta", odometry(k, toVector(truth[k - 1].inverse() * truth[k])));
    if (sigma)
      if (const auto s = sigma(k)) frame.raw.set("odom_sigma", *s);
    EXPECT_TRUE(pre.process(frame));
    pipeline.process(frame);
    EXPECT_TRUE(frame.estimate.valid);
    const SE2 expected = truth.front().inverse() * truth[k];
    const SE2 error = expected.inverse() * Space2D::from3D(frame.estimate.world);
    worst = std::max(worst, error.translation().norm());
    worst_angle = std::max(worst_angle, std::abs(angleOf(error.linear())));
  }
  return {worst, worst_angle};
}

// Prints the tracker's figures after a lap, then checks that no frame failed and that the worst
// error stays within the exact-odometry lap's bounds (its worst error is ~1 cm, 0.3 deg).
void expectLapTracked(const MultiTracker<Space2D>& tracker, const char* label, double worst,
                      double worst_angle) {
  const auto& st = tracker.stats();
  std::printf(
      "%s: %lu aligned, %lu failed, %lu searched, %lu ambiguous, %lu local maps, "
      "worst %.4f m, %.3f deg\n",
      label, static_cast<unsigned long>(st.aligned), static_cast<unsigned long>(st.failed),
      static_cast<unsigned long>(st.searched), static_cast<unsigned long>(st.ambiguous),
      static_cast<unsigned long>(st.local_maps), worst, worst_angle * 180 / M_PI);
  EXPECT_EQ(st.failed, 0u) << label;
  EXPECT_LT(worst, 0.05) << label;
  EXPECT_LT(worst_angle, 0.75 * M_PI / 180) << label;
}

TEST(MultiTracker2D, RecoversASyntheticTrajectory) {
  for (const char* association : {"kdtree", "projective"}) {
    MultiTracker<Space2D> tracker;
    auto aligner = std::make_shared<MultiAligner<Space2D>>();
    auto slice = std::make_shared<PointToLineSlice>();
    slice->association = association;
    slice->configure();
    aligner->slices.assign(slice);
    tracker.aligner.assign(aligner);
    tracker.slices.assign(std::make_shared<PointMapSlice>());
    tracker.splitter.assign(std::make_shared<DistanceSplitter>());
    tracker.motion.assign(std::make_shared<OdometryIncrement>());
    tracker.configure();
    // Odometry with a 2% scale error and a small heading bias.
    const auto [worst, worst_angle] = trackLap(tracker, [](size_t, const Eigen::Vector3d& d) {
      return se2(1.02 * d.x(), 1.02 * d.y(), d.z() + 0.002);
    });
    expectLapTracked(tracker, association, worst, worst_angle);
    EXPECT_GT(tracker.stats().local_maps, 5u);
  }
}

// The lap with exact odometry except at frame `bad`, whose increment is off by 1 m (0.6, 0.8)
// and 30 deg, with the standard deviations `bad_sigma` (m, rad) for it.
std::pair<double, double> lapWithOnePoorPrediction(MultiTracker<Space2D>& tracker, size_t bad,
                                                   const Eigen::Vector2d& bad_sigma) {
  return trackLap(
      tracker,
      [bad](size_t k, const Eigen::Vector3d& d) {
        return k == bad ? se2(d.x() + 0.6, d.y() + 0.8, d.z() + M_PI / 6)
                        : se2(d.x(), d.y(), d.z());
      },
      lap(), 0.1,
      [bad, bad_sigma](size_t k) {
        return k == bad ? std::optional<Eigen::Vector2d>(bad_sigma) : std::nullopt;
      });
}

// A laser tracker with the odometry increments as motion model or, without `odometry`, the
// constant-velocity prediction.
void build(MultiTracker<Space2D>& tracker, bool odometry = true) {
  auto aligner = std::make_shared<MultiAligner<Space2D>>();
  aligner->slices.assign(std::make_shared<PointToLineSlice>());
  aligner->configure();
  tracker.aligner.assign(aligner);
  tracker.slices.assign(std::make_shared<PointMapSlice>());
  tracker.splitter.assign(std::make_shared<DistanceSplitter>());
  if (odometry) tracker.motion.assign(std::make_shared<OdometryIncrement>());
  tracker.configure();
}

TEST(MultiTracker2D, RecoversFromAPredictionOffByOneMetreAndThirtyDegrees) {
  // Frame 40 (mid-leg, 0.15 m steps) is predicted 1 m and 30 deg off. When its covariance says
  // so (0.5 m, 0.3 rad: a reading long after its frame, a slip the model knows of), the search
  // covers the error and the frame is found; nothing fails.
  MultiTracker<Space2D> tracker;
  build(tracker);
  const auto [worst, worst_angle] =
      lapWithOnePoorPrediction(tracker, 40, Eigen::Vector2d(0.5, 0.3));
  expectLapTracked(tracker, "covered", worst, worst_angle);

  // When the model claims 5 cm and 0.05 rad, the error is far outside what it allows: the frame
  // may fail, but it must not be taken silently at a wrong pose.
  MultiTracker<Space2D> confident;
  build(confident);
  const auto [c_worst, c_angle] =
      lapWithOnePoorPrediction(confident, 40, Eigen::Vector2d(0.05, 0.05));
  std::printf("claimed sure: %lu failed, worst %.4f m, %.3f deg\n",
              static_cast<unsigned long>(confident.stats().failed), c_worst, c_angle * 180 / M_PI);
  EXPECT_TRUE(confident.stats().failed > 0 || (c_worst < 0.05 && c_angle < 0.75 * M_PI / 180));
}

// Laser only at a slow scan rate (1 s between scans): 0.5 m steps that stop, start and turn one
// way then the other (0.5 rad per frame), so the constant-velocity prediction is off by a whole
// step (0.5 m, or 1 rad where the turn reverses), which the largest plausible accelerations
// over a second cover.
std::vector<SE2> stopAndGo() {
  std::vector<SE2> poses;
  SE2 t = se2(1.5, 1.5, 0.0);
  poses.push_back(t);
  auto go = [&](int steps, double step, double turn) {
    for (int i = 0; i < steps; ++i) {
      t = t * se2(step, 0.0, turn);
      poses.push_back(t);
    }
  };
  go(6, 0.5, 0.0);
  go(2, 0.0, 0.0);
  go(4, 0.5, 0.0);
  go(3, 0.0, 0.5);
  go(3, 0.0, -0.5);
  go(3, 0.0, 0.5);
  go(4, 0.5, 0.0);
  go(2, 0.0, 0.0);
  go(3, 0.5, 0.0);
  return poses;
}

TEST(MultiTracker2D, LaserOnlyTheConstantVelocityWindowCoversStopsAndTurns) {
  MultiTracker<Space2D> tracker;
  build(tracker, false);
  const auto unused = [](size_t, const Eigen::Vector3d& d) { return se2(d.x(), d.y(), d.z()); };
  const auto [worst, worst_angle] = trackLap(tracker, unused, stopAndGo(), 1.0);
  expectLapTracked(tracker, "laser only", worst, worst_angle);
}

// A corridor whose ends the scan does not see: every pose along its axis fits the walls alike.
// The search reports the match as ambiguous with its rival along the axis, and the information
// along the axis is cut to what the two poses leave known; across it stays.
TEST(MultiAligner, ACorridorIsAmbiguousAlongItsAxis) {
  const auto world = test::corridor(-50, 50, 1.5);
  test::ScanSpec spec;
  spec.range_max = 8;
  spec.noise = 0.005;
  const SE2 a = se2(0.0, 0.0, 0.0);
  const SE2 offset = se2(0.3, 0.05, 0.02);
  ScanPreprocessor pre;
  pre.configure();
  Frame frame;
  frame.raw.set("front_laser", test::castScan(world, a * offset, spec));
  ASSERT_TRUE(pre.process(frame));
  Frame map_frame;
  map_frame.raw.set("front_laser", test::castScan(world, a, spec));
  ASSERT_TRUE(pre.process(map_frame));
  PropertyContainer scene;
  scene.set("front", *map_frame.measurement.find<PointCloud2D>("front"));
  MultiAligner<Space2D> aligner;
  aligner.slices.assign(std::make_shared<PointToLineSlice>());
  aligner.configure();
  AlignContext<Space2D> context{SE2::Identity(), SE2::Identity()};
  context.covariance = Eigen::Vector3d(0.5 * 0.5, 0.5 * 0.5, 0.05 * 0.05).asDiagonal();
  const AlignResult<Space2D> r = aligner.align(frame, scene, context);
  std::printf("corridor: valid %d ambiguous %d rival (%.3f %.3f %.3f) H diag (%.1f %.1f %.1f)\n",
              r.valid, r.ambiguous, r.rival(0), r.rival(1), r.rival(2), r.H(0, 0), r.H(1, 1),
              r.H(2, 2));
  ASSERT_TRUE(r.valid);
  EXPECT_TRUE(r.ambiguous);
  EXPECT_GE(std::abs(r.rival(0)), 0.5);
  EXPECT_LT(std::abs(r.rival(1)), 0.1);
  // Across the axis the pose is right; along it, the covariance reaches the rival (a standard
  // deviation of at least half the way to it), across it stays tight.
  EXPECT_NEAR(r.pose.translation().y(), offset.translation().y(), 0.02);
  const Eigen::Matrix3d covariance = r.H.inverse();
  EXPECT_GE(std::sqrt(covariance(0, 0)), 0.45 * std::abs(r.rival(0)));
  EXPECT_LT(std::sqrt(covariance(1, 1)), 0.01);
}

}  // namespace
}  // namespace plugslam::laser2d
