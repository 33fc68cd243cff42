// A MultiTracker2D built in code with the laser2d modules recovers a synthetic trajectory, with
// motion predicted from biased odometry increments.
#include <gtest/gtest.h>

#include <optional>

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
    Pipeline pipeline;  // places the local maps and composes the world pose
    pipeline.tracker.assign(std::shared_ptr<Tracker>(std::shared_ptr<Tracker>(), &tracker));
    ScanPreprocessor pre;
    pre.configure();

    const auto world = office();
    const auto truth = lap();
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
      // Odometry with a 2% scale error and a small heading bias.
      if (k > 0) {
        const Eigen::Vector3d d = toVector(truth[k - 1].inverse() * truth[k]);
        frame.raw.set("odom_delta", se2(1.02 * d.x(), 1.02 * d.y(), d.z() + 0.002));
      }
      ASSERT_TRUE(pre.process(frame));
      pipeline.process(frame);
      ASSERT_TRUE(frame.estimate.valid);
      const SE2 expected = truth.front().inverse() * truth[k];
      const SE2 error = expected.inverse() * Space2D::from3D(frame.estimate.world);
      worst = std::max(worst, error.translation().norm());
      worst_angle = std::max(worst_angle, std::abs(angleOf(error.linear())));
    }
    std::printf("%s: %zu frames, worst error %.4f m, %.3f deg; %lu aligned, %lu local maps\n",
                association, truth.size(), worst, worst_angle * 180 / M_PI,
                static_cast<unsigned long>(tracker.stats().aligned),
                static_cast<unsigned long>(tracker.stats().local_maps));
    EXPECT_EQ(tracker.stats().failed, 0u) << association;
    EXPECT_LT(worst, 0.05) << association;
    EXPECT_LT(worst_angle, 0.75 * M_PI / 180) << association;
    EXPECT_GT(tracker.stats().local_maps, 5u);
  }
}

}  // namespace
}  // namespace plugslam::laser2d
