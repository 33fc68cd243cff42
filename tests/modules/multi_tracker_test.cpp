// The generic Multi-Aligner and Multi-Tracker on a synthetic landmark cue.
#include "plugslam/multi_tracker.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <optional>
#include <random>

#include "landmark_cue.h"
#include "plugslam/localizer.h"
#include "plugslam/pipeline.h"
#include "plugslam/registry.h"
#include "plugslam/slice_check.h"

using namespace plugslam;
using namespace plugslam::testing;

namespace {

Landmarks grid(double step, double extent) { return jitteredGrid(step, extent, 7); }

}  // namespace

TEST(MultiAligner, RecoversAKnownOffsetWithOneSlice) {
  registerLandmarkCue();
  const Landmarks world = grid(2.0, 8.0);
  MultiAligner<Space2D> aligner;
  aligner.slices.assign(Registry::instance().create("lmtest.LandmarkSlice"));
  PropertyContainer scene;
  scene.set<Landmarks>("landmarks", world);  // the map frame is the world frame
  const Eigen::Isometry2d truth = se2(0.3, -0.2, 0.1);
  Frame frame;
  frame.measurement.set<Landmarks>("landmarks", observe(world, truth, 6.0));
  AlignResult<Space2D> r = aligner.align(
      frame, scene,
      AlignContext<Space2D>{Eigen::Isometry2d::Identity(), Eigen::Isometry2d::Identity()});
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.converged);
  EXPECT_LT((toVector(r.pose) - toVector(truth)).norm(), 1e-9);
  EXPECT_GT(r.inliers, 10u);
  EXPECT_DOUBLE_EQ(r.overlap(), 1.0);
  EXPECT_GT(r.H.determinant(), 0);
}

TEST(MultiAligner, NamesWhyAnAlignmentFailed) {
  // Issue 20: every invalid alignment says why (the tracker counts and logs it).
  registerLandmarkCue();
  MultiAligner<Space2D> aligner;
  aligner.slices.assign(Registry::instance().create("lmtest.LandmarkSlice"));
  const AlignContext<Space2D> at_origin{Eigen::Isometry2d::Identity(),
                                        Eigen::Isometry2d::Identity()};
  const Landmarks world = grid(2.0, 8.0);
  PropertyContainer scene;
  scene.set<Landmarks>("landmarks", world);
  Frame good;
  good.measurement.set<Landmarks>("landmarks", observe(world, Eigen::Isometry2d::Identity(), 6.0));
  AlignResult<Space2D> r = aligner.align(good, scene, at_origin);
  EXPECT_TRUE(r.valid);
  EXPECT_EQ(r.failure, AlignFailure::none);

  Frame empty;  // no landmark entry: no slice binds
  r = aligner.align(empty, scene, at_origin);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.failure, AlignFailure::no_data);
  EXPECT_STREQ(toString(r.failure), "no_data");

  aligner.min_inliers = 100000;
  r = aligner.align(good, scene, at_origin);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.failure, AlignFailure::too_few_inliers);

  // One landmark at the robot's position fixes x and y but not the heading: degenerate, and
  // the weakest direction is the rotation.
  aligner.min_inliers = 1;
  PropertyContainer one;
  one.set<Landmarks>("landmarks", Landmarks{Eigen::Vector2d(0, 0)});
  Frame single;
  single.measurement.set<Landmarks>("landmarks", Landmarks{Eigen::Vector2d(0, 0)});
  r = aligner.align(single, one, at_origin);
  EXPECT_FALSE(r.valid);
  EXPECT_EQ(r.failure, AlignFailure::degenerate);
  EXPECT_NEAR(std::abs(r.weakest(2)), 1.0, 1e-9);
}

TEST(MultiAligner, CountsFactorsInliersAndCandidatesPerSlice) {
  // Two slices on two landmark cues: the result's totals are the sums of the per-slice counts,
  // and each slice's are its own cue's (every landmark seen is a candidate; the ones the map
  // has make factors).
  registerLandmarkCue();
  const Landmarks world = grid(2.0, 8.0);
  MultiAligner<Space2D> aligner;
  auto near = std::make_shared<LandmarkSlice>(), far = std::make_shared<LandmarkSlice>();
  near->setName("near");
  far->setName("far");
  far->measurement = "far";
  far->scene = "far";
  aligner.slices.assign(near);
  aligner.slices.assign(far);
  const Eigen::Isometry2d truth = se2(0.3, -0.2, 0.1);
  PropertyContainer scene;
  scene.set<Landmarks>("landmarks", world);
  Landmarks half = world;
  half.resize(world.size() / 2);  // the map knows only the first half of the far cue
  scene.set<Landmarks>("far", half);
  Frame frame;
  const Landmarks seen = observe(world, truth, 6.0), seen_far = observe(world, truth, 12.0);
  frame.measurement.set<Landmarks>("landmarks", seen);
  frame.measurement.set<Landmarks>("far", seen_far);
  auto count = [](const Landmarks& l, size_t n) {
    size_t k = 0;
    for (size_t i = 0; i < std::min(n, l.size()); ++i) k += l[i].allFinite();
    return k;
  };
  const AlignResult<Space2D> r =
      aligner.align(frame, scene, {Eigen::Isometry2d::Identity(), Eigen::Isometry2d::Identity()});
  ASSERT_TRUE(r.valid);
  ASSERT_EQ(r.cues.size(), 2u);
  EXPECT_EQ(r.cues[0].slice, "near");
  EXPECT_EQ(r.cues[0].candidates, count(seen, seen.size()));
  EXPECT_EQ(r.cues[0].factors, count(seen, seen.size()));
  EXPECT_EQ(r.cues[1].slice, "far");
  EXPECT_EQ(r.cues[1].candidates, count(seen_far, seen_far.size()));
  EXPECT_EQ(r.cues[1].factors, count(seen_far, half.size()));
  EXPECT_LT(r.cues[1].factors, r.cues[1].candidates);
  EXPECT_EQ(r.factors, r.cues[0].factors + r.cues[1].factors);
  EXPECT_EQ(r.inliers, r.cues[0].inliers + r.cues[1].inliers);
  EXPECT_EQ(r.candidates, r.cues[0].candidates + r.cues[1].candidates);
  EXPECT_DOUBLE_EQ(r.cues[1].overlap(), double(r.cues[1].factors) / r.cues[1].candidates);
  EXPECT_NE(describeCues(r.cues).find("far: "), std::string::npos) << describeCues(r.cues);
}

TEST(LandmarkSlice, EveryFactorPassesTheJacobianCheck) {
  registerLandmarkCue();
  const Landmarks world = grid(2.0, 8.0);
  LandmarkSlice slice;
  PropertyContainer scene;
  scene.set<Landmarks>("landmarks", world);
  Frame frame;
  frame.measurement.set<Landmarks>("landmarks", observe(world, se2(0.3, -0.2, 0.1), 6.0));
  ASSERT_TRUE(slice.bind(frame, scene, {}));
  for (const Eigen::Isometry2d& t : {se2(0, 0, 0), se2(0.3, -0.2, 0.1), se2(-1, 2, 2.5)}) {
    const SliceJacobianCheck r = checkSliceJacobians(slice, t);
    EXPECT_GT(r.factors, 10u);
    EXPECT_TRUE(r.ok()) << r;
  }
}

TEST(AlignerSlice, AnAbsentEntrySitsTheFrameOut) {
  // bind() binds every entry; with the scene entry missing the slice adds nothing.
  registerLandmarkCue();
  LandmarkSlice slice;
  Frame frame;
  frame.measurement.set<Landmarks>("landmarks", Landmarks{{1.0, 2.0}});
  PropertyContainer scene;
  EXPECT_FALSE(slice.bind(frame, scene, {}));
  EXPECT_TRUE(slice.measurement.bound());
  EXPECT_FALSE(slice.scene.bound());
  scene.set<Landmarks>("landmarks", Landmarks{{1.0, 2.0}});
  EXPECT_TRUE(slice.bind(frame, scene, {}));
  EXPECT_EQ(slice.scene->size(), 1u);
  // A property of another type is an error, not an absent cue.
  frame.measurement.set<double>("other", 1.0);
  slice.measurement = "other";
  EXPECT_THROW(slice.bind(frame, scene, {}), PropertyTypeMismatch);
}

TEST(MultiAligner, NoSliceOrNoDataIsInvalidNotACrash) {
  MultiAligner<Space2D> aligner;
  Frame frame;
  PropertyContainer scene;
  auto r = aligner.align(frame, scene, {Eigen::Isometry2d::Identity(), se2(1, 2, 0.3)});
  EXPECT_FALSE(r.valid);
  EXPECT_LT((toVector(r.pose) - Eigen::Vector3d(1, 2, 0.3)).norm(), 1e-12);
}

TEST(MultiTracker, TracksACircleAndSplitsLocalMaps) {
  auto tracker = landmarkTracker(1.0);
  auto pipeline = trackingOnly(tracker);
  const Landmarks world = grid(1.5, 12.0);
  std::vector<Eigen::Isometry2d> truth;
  for (int i = 0; i < 200; ++i) {
    double a = 2 * M_PI * i / 200.0;
    truth.push_back(se2(5 * std::cos(a), 5 * std::sin(a), a + M_PI / 2));
  }
  double worst = 0;
  for (size_t i = 0; i < truth.size(); ++i) {
    Frame f = sequenceFrame(i);
    // Observations in the robot frame; the world frame of the estimate is the first pose's.
    f.measurement.set<Landmarks>("landmarks", observe(world, truth[i], 6.0));
    pipeline->process(f);
    ASSERT_TRUE(f.estimate.valid);
    Eigen::Isometry2d expected = truth[0].inverse() * truth[i];
    worst = std::max(
        worst, Space2D::toVector(expected.inverse() * Space2D::from3D(f.estimate.world)).norm());
  }
  // Exact landmarks; the constant-velocity prior (a factor with its covariance, which on a
  // circle driven exactly learns the floor of its typical error, 1 cm) moves the solution by
  // about a millimetre on the turn.
  EXPECT_LT(worst, 2e-3);
  // 31.4 m of travel with a split every metre.
  EXPECT_GT(tracker->stats().local_maps, 25u);
  EXPECT_EQ(tracker->stats().failed, 0u);
  const auto maps = pipeline->result().local_maps;
  ASSERT_EQ(maps.size(), tracker->stats().local_maps);
  for (size_t k = 1; k < maps.size(); ++k) {
    EXPECT_EQ(maps[k]->previous, maps[k - 1]->id);
    EXPECT_EQ(maps[k]->information.rows(), 3);
  }
}

namespace {
// A tracker slice that refines each frame it merges by 5 cm to the left (as a bundle adjustment
// would move it by what its map knows).
class NudgingSlice : public TrackerSlice<Space2D>, public RefiningSlice<Space2D> {
 public:
  std::optional<Eigen::Isometry2d> refinedPose() const override { return refined_; }

 protected:
  void integrate(const MergeContext<Space2D>& context) override {
    refined_ = context.pose * se2(0.0, 0.05, 0.0);
  }

 private:
  std::optional<Eigen::Isometry2d> refined_;
};
}  // namespace

TEST(MultiTracker, TakesTheRefinedPoseOfARefiningSlice) {
  auto tracker = landmarkTracker(100.0);
  tracker->slices.assign(std::make_shared<NudgingSlice>());
  auto pipeline = trackingOnly(tracker);
  const Landmarks world = grid(1.5, 12.0);
  for (uint64_t i = 0; i < 4; ++i) {
    Frame f = sequenceFrame(i);
    f.measurement.set<Landmarks>("landmarks", observe(world, Eigen::Isometry2d::Identity(), 6.0));
    pipeline->process(f);
    ASSERT_TRUE(f.estimate.valid);
    // The landmarks place the standing robot at the origin; the refining slice has the last word.
    EXPECT_NEAR(f.estimate.world.translation().x(), 0.0, 1e-6) << "frame " << i;
    EXPECT_NEAR(f.estimate.world.translation().y(), 0.05, 1e-6) << "frame " << i;
  }
}

TEST(MultiTracker, ReportsTheMapsItStartsAndCloses) {
  // A split every metre at 0.1 m per frame: every 10th frame closes the map and starts the next;
  // a reset closes the map at once and the next frame starts a new chain.
  auto tracker = landmarkTracker(1.0);
  const Landmarks world = grid(1.5, 12.0);
  std::vector<std::shared_ptr<LocalMap>> started, closed;
  for (int i = 0; i < 40; ++i) {
    if (i == 25) tracker->reset();
    Frame f = sequenceFrame(i);
    f.measurement.set<Landmarks>("landmarks", observe(world, se2(0.1 * i, 0, 0), 6.0));
    const TrackEvents events = tracker->track(f);
    if (events.started) {
      started.push_back(events.started);
      EXPECT_EQ(f.estimate.local_map, events.started->id) << i;
    }
    for (const auto& m : events.closed) {
      // A map closes once, after it started, and never is the one the frame is in.
      EXPECT_NE(m->id, f.estimate.local_map) << i;
      EXPECT_TRUE(std::find(closed.begin(), closed.end(), m) == closed.end()) << i;
      EXPECT_TRUE(std::find(started.begin(), started.end(), m) != started.end()) << i;
      closed.push_back(m);
    }
  }
  ASSERT_EQ(started.size(), tracker->stats().local_maps);
  EXPECT_EQ(closed.size(), started.size() - 1);  // the last one is still open
  for (size_t k = 0; k < started.size(); ++k) EXPECT_EQ(started[k]->id, static_cast<int64_t>(k));
  // The map started after the reset follows none; the others follow their predecessor.
  int chains = 0;
  for (const auto& m : started) chains += m->previous < 0;
  EXPECT_EQ(chains, 2);
}

TEST(MultiTracker, AFrameWithoutDataStartsANewMapAndTrackingGoesOn) {
  auto tracker = landmarkTracker(100.0);
  auto pipeline = trackingOnly(tracker);
  const Landmarks world = grid(1.5, 12.0);
  for (int i = 0; i < 30; ++i) {
    Frame f = sequenceFrame(i);
    const Eigen::Isometry2d pose = se2(0.1 * i, 0, 0);
    if (i != 15) f.measurement.set<Landmarks>("landmarks", observe(world, pose, 6.0));
    pipeline->process(f);
    if (i > 16) {
      EXPECT_LT((f.estimate.world.translation().head<2>() - pose.translation()).norm(), 1e-4) << i;
    }
  }
  EXPECT_EQ(tracker->stats().failed, 1u);
  EXPECT_EQ(tracker->stats().local_maps, 2u);
}

// What a sink learns from an estimate: whether its map may still move (frozen: localization in
// saved maps) and whether the frame was measured or only predicted (lost).
TEST(MultiTracker, EstimatesSayWhetherTheMapIsFrozenAndWhetherTheFrameWasLost) {
  const Landmarks world = grid(1.5, 12.0);
  // Frame i of a drive along x through `pipeline`, without data at frame `lost`: the estimate is
  // valid, lost at that frame only, and in a map `frozen` or not.
  auto drive = [&](Pipeline& pipeline, int i, int lost, bool frozen) {
    Frame f = sequenceFrame(i);
    if (i != lost)
      f.measurement.set<Landmarks>("landmarks", observe(world, se2(0.1 * i, 0, 0), 6.0));
    pipeline.process(f);
    EXPECT_TRUE(f.estimate.valid) << i;
    EXPECT_EQ(f.estimate.frozen, frozen) << i;
    EXPECT_EQ(f.estimate.lost, i == lost) << i;
    return f;
  };
  auto mapper = landmarkTracker(1.0);
  auto mapping = trackingOnly(mapper);
  for (int i = 0; i < 30; ++i) drive(*mapping, i, 15, false);
  // The session's maps, as a run saved and another loads them: localization swaps in the
  // tracker's localizer.
  std::vector<std::shared_ptr<LocalMap>> maps;
  for (const auto& m : mapping->result().local_maps) maps.push_back(std::make_shared<LocalMap>(*m));
  auto localizing = trackingOnly(landmarkTracker(1.0));
  localizing->restoreSession(maps, {}, true);
  ASSERT_TRUE(dynamic_cast<Localizer<Space2D>*>(localizing->tracker.get()));
  const Tracker& localizer = *localizing->tracker;
  for (int i = 0; i < 30; ++i) {
    const Frame f = drive(*localizing, i, 20, true);
    if (i != 20) {
      // Exact landmarks; the constant-velocity prior pulls by millimetres while the velocity
      // is still being learnt.
      EXPECT_LT((f.estimate.world.translation().head<2>() - Eigen::Vector2d(0.1 * i, 0)).norm(),
                5e-3)
          << i;
    }
  }
  EXPECT_EQ(localizer.stats().failed, 1u);
  EXPECT_EQ(localizing->result().local_maps.size(), maps.size());  // nothing was created
}

namespace {

// The path of the ParamError that configure() throws ("" if it throws none).
std::string configureError(Configurable& tracker) {
  try {
    tracker.configure();
  } catch (const ParamError& e) {
    return e.path();
  }
  return "";
}

template <class S>
void expectSlicesRequired() {
  MultiTracker<S> tracker;
  EXPECT_EQ(configureError(tracker), "aligner") << S::kSuffix;
  tracker.aligner.assign(std::make_shared<MultiAligner<S>>());
  EXPECT_EQ(configureError(tracker), "aligner.slices") << S::kSuffix;
}

}  // namespace

// Item 17.7: without aligner slices no frame can be aligned; the tracker used to "track" every
// frame at the prediction. That is a configuration error. Tracker slices are optional (an
// odometry prior alone is dead reckoning and needs no map).
TEST(MultiTracker, ATrackerWithoutAlignerSlicesIsAConfigurationError) {
  expectSlicesRequired<Space2D>();
  expectSlicesRequired<Space3D>();
  auto tracker = landmarkTracker(1.0);
  tracker->slices.clear();
  EXPECT_EQ(configureError(*tracker), "");
}

TEST(MultiTracker, FallbackSigmaIsValidated) {
  auto tracker = landmarkTracker(1.0);
  tracker->fallback_sigma = std::vector<double>{0.1, 0.1};
  EXPECT_THROW(tracker->configure(), ParamError);
}

namespace {

// Predicts a scripted motion per frame (by seq) with a 1 m, 1 rad standard deviation; nothing
// for frames not in the script.
class ScriptedMotion : public MotionModel<Space2D> {
 public:
  std::map<uint64_t, Eigen::Isometry2d> script;
  std::optional<uint64_t> predicts_nothing_at;  ///< a frame without a reading
  std::optional<MotionEstimate<Space2D>> predict(const Frame& frame) override {
    auto it = script.find(frame.seq);
    if (it == script.end() || frame.seq == predicts_nothing_at) return std::nullopt;
    MotionEstimate<Space2D> e;
    e.mean = it->second;
    e.covariance.setIdentity();
    return e;
  }
};

// Drives along x at 0.1 m per frame for 30 frames, predicted by `motion` (its script: 0.1 m,
// except at frame 15, where it predicts 0.5 m too far), and returns the estimates.
std::vector<Eigen::Isometry2d> driveWithABadPrediction(
    const std::shared_ptr<MultiTracker<Space2D>>& tracker,
    const std::shared_ptr<ScriptedMotion>& motion) {
  for (uint64_t i = 1; i < 30; ++i) motion->script[i] = se2(i == 15 ? 0.6 : 0.1, 0, 0);
  tracker->motion.assign(motion);
  auto pipeline = trackingOnly(tracker);
  const Landmarks world = grid(1.5, 12.0);
  std::vector<Eigen::Isometry2d> out;
  for (int i = 0; i < 30; ++i) {
    Frame f = sequenceFrame(i);
    f.measurement.set<Landmarks>("landmarks", observe(world, se2(0.1 * i, 0, 0), 6.0));
    pipeline->process(f);
    out.push_back(Space2D::from3D(f.estimate.world));
  }
  return out;
}

// The same drive, where the motion model also predicts nothing at frame 20.
std::vector<Eigen::Isometry2d> driveWithABadPrediction(
    const std::shared_ptr<MultiTracker<Space2D>>& tracker) {
  auto motion = std::make_shared<ScriptedMotion>();
  motion->predicts_nothing_at = 20;
  return driveWithABadPrediction(tracker, motion);
}

}  // namespace

TEST(MultiTracker, TheAlignmentCorrectsAPredictionItsCovarianceCallsUncertain) {
  // The (exact) landmark alignment corrects the bad prediction: the prior, a factor with the
  // prediction's 1 m covariance, barely pulls it; the frame without a prediction passes.
  auto tracker = landmarkTracker(100.0);
  auto estimates = driveWithABadPrediction(tracker);
  EXPECT_EQ(tracker->stats().failed, 0u);
  EXPECT_NEAR(estimates[15].translation().x(), 1.5, 1e-3);
  EXPECT_NEAR(estimates[29].translation().x(), 2.9, 1e-3);
}

// Item 18.6: a frame that failed to align must not enter the map it failed against (its data
// would sit there at the unverified predicted pose); it seeds the next map instead.
TEST(MultiTracker, AFrameThatFailedToAlignLeavesTheOldMapUnchanged) {
  auto tracker = landmarkTracker(100.0);
  auto motion = std::make_shared<ScriptedMotion>();
  // 0.1 m per frame; frame 15 sees too few of the map's landmarks to align (below), so it
  // fails and keeps the prediction.
  for (uint64_t i = 1; i < 20; ++i) motion->script[i] = se2(0.1, 0, 0);
  tracker->motion.assign(motion);
  const Landmarks world = grid(1.5, 12.0);
  std::shared_ptr<LocalMap> first;
  Landmarks before;  // the first map's landmarks after frame 14
  for (int i = 0; i < 20; ++i) {
    Frame f = sequenceFrame(i);
    Landmarks seen = observe(world, se2(0.1 * i, 0, 0), 6.0);
    // Frame 15 sees only three of them, too few to align, and a landmark no other frame sees,
    // so merging it would change the old map.
    if (i == 15) {
      int kept = 0;
      for (auto& l : seen)
        if (l.allFinite() && ++kept > 3) l.setConstant(std::numeric_limits<double>::quiet_NaN());
      seen.emplace_back(2.0, 1.0);
    }
    f.measurement.set<Landmarks>("landmarks", seen);
    const TrackEvents events = tracker->track(f);
    if (i == 0) first = events.started;
    ASSERT_TRUE(first);
    if (i == 14) before = *first->scene.find<Landmarks>("landmarks");
    if (i != 15) continue;
    ASSERT_EQ(events.closed.size(), 1u);
    EXPECT_TRUE(events.closed[0] == first);
    ASSERT_TRUE(events.started);
    EXPECT_TRUE(f.estimate.lost);
    // The failed frame had something new to add...
    int unseen = 0;
    for (size_t k = 0; k < seen.size(); ++k)
      unseen += seen[k].allFinite() && (k >= before.size() || !before[k].allFinite());
    EXPECT_GT(unseen, 0);
    // ...but the old map is exactly as frame 14 left it (NaN = not mapped),
    const Landmarks& after = *first->scene.find<Landmarks>("landmarks");
    ASSERT_EQ(after.size(), before.size());  // the extra landmark's id is not in it
    for (size_t k = 0; k < after.size(); ++k) {
      EXPECT_EQ(after[k].allFinite(), before[k].allFinite()) << k;
      if (after[k].allFinite()) {
        EXPECT_TRUE(after[k] == before[k]) << k;
      }
    }
    EXPECT_EQ(first->last_seq, 14u);
    // and the frame seeds the new map: every landmark it saw, in the new map's frame (the
    // frame's own pose is its origin).
    const Landmarks& seeded = *events.started->scene.find<Landmarks>("landmarks");
    for (size_t k = 0; k < seen.size(); ++k) {
      if (!seen[k].allFinite()) continue;
      ASSERT_LT(k, seeded.size());
      EXPECT_LT((seeded[k] - seen[k]).norm(), 1e-9) << k;
    }
  }
  // Frame 16 sees the landmarks frame 15's map lacks, too few of them in it to align: it fails
  // too and seeds a third map, which frame 17 on tracks against.
  EXPECT_EQ(tracker->stats().failed, 2u);
  EXPECT_EQ(tracker->stats().local_maps, 3u);
}
