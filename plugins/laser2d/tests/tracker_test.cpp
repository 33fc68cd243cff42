// A MultiTracker2D built in code with the laser2d modules recovers a synthetic trajectory, with
// motion predicted from biased odometry increments.
#include <gtest/gtest.h>

#include <functional>
#include <optional>
#include <utility>

#include "plugslam/multi_tracker.h"
#include "plugslam/pipeline.h"
#include "correlative_seeder.h"
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

// Motion prediction from the increment the frame carries (biased odometry, built below).
class OdometryIncrement final : public MotionModel<Space2D> {
 public:
  std::optional<SE2> predict(const Frame& frame) override {
    if (const SE2* d = frame.raw.find<SE2>("odom_delta")) return *d;
    return std::nullopt;
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
    const std::vector<SE2>& truth = lap()) {
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
    frame.stamp = 0.1 * k;
    frame.raw.set("front_laser", test::castScan(world, truth[k], spec));
    if (k > 0)
      frame.raw.set("odom_delta", odometry(k, toVector(truth[k - 1].inverse() * truth[k])));
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
    std::printf("%s: %zu frames, worst error %.4f m, %.3f deg; %lu aligned, %lu local maps\n",
                association, lap().size(), worst, worst_angle * 180 / M_PI,
                static_cast<unsigned long>(tracker.stats().aligned),
                static_cast<unsigned long>(tracker.stats().local_maps));
    EXPECT_EQ(tracker.stats().failed, 0u) << association;
    EXPECT_LT(worst, 0.05) << association;
    EXPECT_LT(worst_angle, 0.75 * M_PI / 180) << association;
    EXPECT_GT(tracker.stats().local_maps, 5u);
  }
}

// The lap with exact odometry except at frame `bad`, whose increment is off by 1 m (0.6, 0.8)
// and 30 deg.
std::pair<double, double> lapWithOnePoorPrediction(MultiTracker<Space2D>& tracker, size_t bad) {
  return trackLap(tracker, [bad](size_t k, const Eigen::Vector3d& d) {
    return k == bad ? se2(d.x() + 0.6, d.y() + 0.8, d.z() + M_PI / 6) : se2(d.x(), d.y(), d.z());
  });
}

void build(MultiTracker<Space2D>& tracker, bool seeded) {
  auto aligner = std::make_shared<MultiAligner<Space2D>>();
  aligner->slices.assign(std::make_shared<PointToLineSlice>());
  if (seeded) aligner->seeder.assign(std::make_shared<CorrelativeSeeder>());
  aligner->configure();
  tracker.aligner.assign(aligner);
  tracker.slices.assign(std::make_shared<PointMapSlice>());
  tracker.splitter.assign(std::make_shared<DistanceSplitter>());
  tracker.motion.assign(std::make_shared<OdometryIncrement>());
  tracker.max_correction = std::vector<double>{0.3, 0.5};  // the shipped config's gate
  // A seed beyond the gate (the 1 m / 30 deg frame) needs twice the prediction's support.
  tracker.seed_beyond_gate = 2.0;
  tracker.configure();
}

TEST(MultiTracker2D, RecoversFromAPredictionOffByOneMetreAndThirtyDegrees) {
  // Issue 20: frame 40 (mid-leg, 0.15 m steps) is predicted 1 m and 30 deg off. Without a
  // seeder the ICP solve from there fails or is gated, and the prediction's error stays in the
  // trajectory; with the correlative seeder the frame is recovered and nothing fails.
  MultiTracker<Space2D> plain;
  build(plain, false);
  const auto [plain_worst, plain_angle] = lapWithOnePoorPrediction(plain, 40);
  std::printf("without seeder: %lu failed, worst %.3f m, %.2f deg\n",
              static_cast<unsigned long>(plain.stats().failed), plain_worst,
              plain_angle * 180 / M_PI);
  // The kept prediction is off by 1 m / 30 deg; the bound leaves room for partial corrections.
  EXPECT_GT(plain_worst, 0.5);

  MultiTracker<Space2D> seeded;
  build(seeded, true);
  const auto [worst, worst_angle] = lapWithOnePoorPrediction(seeded, 40);
  std::printf("with seeder: %lu failed, %lu recovered, worst %.4f m, %.3f deg\n",
              static_cast<unsigned long>(seeded.stats().failed),
              static_cast<unsigned long>(seeded.stats().recovered), worst,
              worst_angle * 180 / M_PI);
  EXPECT_EQ(seeded.stats().failed, 0u);
  EXPECT_GE(seeded.stats().recovered, 1u);
  // Same bounds as the exact-odometry lap above (its worst error is ~1 cm, 0.3 deg).
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(worst_angle, 0.75 * M_PI / 180);
}

// Laser only at a slow scan rate: 0.5 m steps that stop, start and turn one way then the
// other (0.5 rad per frame), so the constant-velocity prediction is off by a whole step (0.5 m,
// or 1 rad where the turn reverses).
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

void buildLaserOnly(MultiTracker<Space2D>& tracker, bool seeded) {
  auto aligner = std::make_shared<MultiAligner<Space2D>>();
  aligner->slices.assign(std::make_shared<PointToLineSlice>());
  if (seeded) {
    // The shipped CARMEN config's laser-only search.
    auto seeder = std::make_shared<CorrelativeSeeder>();
    seeder->linear_window = 1.5;
    seeder->angular_window = 1.5;
    seeder->min_score = 0.3;
    seeder->with_measured_motion = false;
    seeder->configure();
    aligner->seeder.assign(seeder);
  }
  aligner->configure();
  tracker.aligner.assign(aligner);
  tracker.slices.assign(std::make_shared<PointMapSlice>());
  tracker.splitter.assign(std::make_shared<DistanceSplitter>());
  tracker.max_correction = std::vector<double>{0.3, 0.5};  // no gate applies: nothing measured
  tracker.configure();
}

TEST(MultiTracker2D, LaserOnlyTheSeedersSearchChecksEveryFrame) {
  // Issue 20, no odometry: without the search the solve from the constant-velocity prediction
  // settles in a wrong minimum at a stop or a reversed turn; with it every frame is recovered.
  const auto unused = [](size_t, const Eigen::Vector3d& d) { return se2(d.x(), d.y(), d.z()); };
  MultiTracker<Space2D> plain;
  buildLaserOnly(plain, false);
  const auto [plain_worst, plain_angle] = trackLap(plain, unused, stopAndGo());
  std::printf("laser only, no search: %lu failed, worst %.3f m, %.2f deg\n",
              static_cast<unsigned long>(plain.stats().failed), plain_worst,
              plain_angle * 180 / M_PI);
  MultiTracker<Space2D> checked;
  buildLaserOnly(checked, true);
  const auto [worst, worst_angle] = trackLap(checked, unused, stopAndGo());
  std::printf("laser only, searched: %lu failed, %lu recovered, worst %.4f m, %.3f deg\n",
              static_cast<unsigned long>(checked.stats().failed),
              static_cast<unsigned long>(checked.stats().recovered), worst,
              worst_angle * 180 / M_PI);
  EXPECT_GT(plain_worst, 0.3);
  EXPECT_EQ(checked.stats().failed, 0u);
  EXPECT_GE(checked.stats().recovered, 1u);
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(worst_angle, 0.75 * M_PI / 180);
}

}  // namespace
}  // namespace plugslam::laser2d
