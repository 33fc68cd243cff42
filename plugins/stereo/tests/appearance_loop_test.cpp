// Appearance loop closing on rendered frames of the simulator's street (a block loop of
// buildings with brick, facade and noise textures): sdk.AppearanceDetector finds the return to
// the start among look-alike places, sdk.AppearanceValidator registers it to the true relative
// pose and rejects every pair of different places, however alike their textures look.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "landmark_tracker.h"
#include "plugslam/landmarks/appearance_detector.h"
#include "plugslam/landmarks/appearance_validator.h"
#include "plugslam/landmarks/landmark_map.h"
#include "plugslam/landmarks/point_registration.h"
#include "rendered_frames.h"
#include "stereo_preprocessor.h"

namespace plugslam {
namespace {

using sim::sim3d::Simulator3D;

Simulator3D street() { return testing::streetStereo(); }

// A local map tracked over `frames` frames from frame `first`: its frame is the camera at
// `first` (the rig's mount is the identity).
std::shared_ptr<LocalMap> placeMap(const Simulator3D& sim, size_t first, size_t frames) {
  visual::StereoPreprocessor pre;
  pre.configure();
  MultiTracker<Space3D> tracker;
  testing::buildLandmarkTracker(tracker, 1000.0);
  std::shared_ptr<LocalMap> map;
  for (size_t k = first; k < first + frames; ++k) {
    Frame frame = testing::renderedFrame(sim, k);
    EXPECT_TRUE(pre.process(frame));
    TrackEvents events = tracker.track(frame);
    if (events.started) map = events.started;
  }
  return map;
}

struct Street {
  Simulator3D sim = street();
  std::vector<size_t> firsts;  // first frame of each place map, in driving order
  GraphView view;
};

// Places along the loop, each 5 frames (4 m): the start, five look-alike places spread over the
// block, and the return to the start (the loop ends where it began: its first frame within 6 m of
// the start, so its 5 frames still fit before the end).
Street drive() {
  Street s;
  const auto& poses = s.sim.trajectory().poses();
  const size_t n = poses.size();
  size_t back = n;
  for (size_t k = n / 2; k < n; ++k)
    if ((poses[k].pose.translation() - poses[0].pose.translation()).norm() < 6.0) {
      back = std::min(k, n - 5);
      break;
    }
  if (back >= n) {
    ADD_FAILURE() << "the block loop returns to its start";
    return s;
  }
  s.firsts = {0};
  for (int i = 1; i <= 5; ++i) s.firsts.push_back(static_cast<size_t>(i) * back / 6);
  s.firsts.push_back(back);
  const std::vector<double> along = s.sim.trajectory().cumulativeDistances();
  for (size_t i = 0; i < s.firsts.size(); ++i) {
    auto map = placeMap(s.sim, s.firsts[i], 5);
    map->id = static_cast<int64_t>(i);
    map->origin = poses[s.firsts[i]].pose;
    s.view.maps.push_back(map);
    s.view.origins.push_back(map->origin);
    s.view.travelled.push_back(along[s.firsts[i]]);
  }
  return s;
}

// Measured on 958f850 (the street and rendered frames from tests/support/rendered_frames.h):
// the return proposes the start first (score 0.133, then look-alike places at 0.088 and below),
// 301 of its 1137 landmarks lie within 0.3 m of the start's under the true relative pose, the
// validator registers it 0.060 m / 0.089 deg from the truth, and all 20 pairs of different places
// are rejected (at most 17 of 34-103 descriptor matches agree on one rigid motion, 20 needed).
// It was disabled after a 05:50 run on the vslam branch before its merge (439 landmarks in the
// return, no candidate even ungated, 0 of them overlapping the start under the assumed truth);
// on main the same test passes, with the figures above. Which merged change made the difference
// was not isolated; this test now guards the result.
TEST(AppearanceLoop, FindsTheRevisitAndRejectsLookAlikePlacesOnTheStreet) {
  const Street s = drive();
  ASSERT_EQ(s.view.maps.size(), 7u);
  const size_t last = s.view.maps.size() - 1;
  for (const auto& m : s.view.maps) {
    const LandmarkMap* lm = m->scene.find<LandmarkMap>("landmarks");
    ASSERT_NE(lm, nullptr);
    EXPECT_GT(lm->size(), 200u) << "place " << m->id;
  }
  AppearanceDetector detector;
  detector.configure();
  std::vector<LoopCandidate> found;
  for (size_t i = 0; i <= last; ++i) {
    found = detector.detect(s.view, *s.view.maps[i]);
    // Proposals between different places are allowed (appearance alone cannot tell a
    // look-alike place): the validator's pairs below must reject them.
    for (const LoopCandidate& c : found)
      std::printf("place %zu proposes %lld (score %.3f)\n", i, static_cast<long long>(c.id),
                  c.score);
  }
  // What the return shares with each place by brute-force matching (for the log).
  const DescribedPoints back_points = describedPoints(*s.view.maps[last]->scene.find<LandmarkMap>("landmarks"));
  for (size_t i = 0; i < last; ++i) {
    const LandmarkMap& lm = *s.view.maps[i]->scene.find<LandmarkMap>("landmarks");
    size_t tracked = 0;
    for (uint32_t o : lm.observations) tracked += o >= 2;
    DescriptorMatchOptions all;
    all.max_hamming = 50;
    all.ratio = 1.0;
    all.mutual = false;
    std::printf("place %zu: %zu landmarks (%zu tracked); the return matches %zu of its %zu\n", i,
                lm.size(), tracked, matchDescriptors(back_points, describedPoints(lm), all).size(),
                back_points.size());
  }
  {
    // Every score the return gets, ungated (for the log).
    AppearanceDetector open;
    open.min_matches = 1;
    open.min_ratio = 0.0;
    open.min_travel = 0.0;
    open.max_candidates = 10;
    open.configure();
    for (size_t i = 0; i <= last; ++i) {
      const std::vector<LoopCandidate> all = open.detect(s.view, *s.view.maps[i]);
      if (i == last)
        for (const LoopCandidate& c : all)
          std::printf("ungated: the return scores %.3f with place %lld\n", c.score,
                      static_cast<long long>(c.id));
    }
    // How many of the return's landmarks lie within 0.3 m of one of the start's under the true
    // relative pose (checks the maps' frames and the true overlap, for the log).
    const LandmarkMap& a = *s.view.maps[0]->scene.find<LandmarkMap>("landmarks");
    const LandmarkMap& b = *s.view.maps[last]->scene.find<LandmarkMap>("landmarks");
    const Eigen::Isometry3d t = s.view.relative(0, last);
    size_t near = 0;
    for (const Eigen::Vector3d& p : b.positions) {
      const Eigen::Vector3d q = t * p;
      for (const Eigen::Vector3d& r : a.positions)
        if ((q - r).norm() < 0.3) {
          ++near;
          break;
        }
    }
    std::printf("true overlap: %zu of the return's %zu landmarks within 0.3 m of the start's\n",
                near, b.size());
  }
  EXPECT_FALSE(found.empty()) << "the return to the start is proposed";
  if (!found.empty()) {
    EXPECT_EQ(found.front().id, 0);
  }

  AppearanceValidator validator;
  validator.configure();
  LoopClosure closure;
  std::string reason;
  ASSERT_TRUE(validator.validate(*s.view.maps[0], *s.view.maps[last], s.view.relative(0, last),
                                 closure, reason))
      << reason;
  const Eigen::Isometry3d truth = s.view.relative(0, last);
  const Eigen::Isometry3d err = truth.inverse() * closure.edge.relative;
  const double t_err = err.translation().norm();
  const double r_err = Eigen::AngleAxisd(err.linear()).angle() * 180 / M_PI;
  std::printf("revisit registered: %.3f m, %.3f deg from the truth, overlap %.2f\n", t_err, r_err,
              closure.overlap);
  // Issue 16's bound on an accepted loop: 0.5 m and 2 deg from the ground truth.
  EXPECT_LT(t_err, 0.5);
  EXPECT_LT(r_err, 2.0);

  // Every pair of different places (all show the street's brick, facade and noise textures).
  int rejected = 0;
  for (size_t a = 0; a < last; ++a)
    for (size_t b = a + 1; b <= last; ++b) {
      if (a == 0 && b == last) continue;
      const bool ok = validator.validate(*s.view.maps[a], *s.view.maps[b],
                                         s.view.relative(a, b), closure, reason);
      EXPECT_FALSE(ok) << "places " << a << " and " << b << " are different";
      if (!ok) ++rejected;
      std::printf("places %zu-%zu: %s\n", a, b, ok ? "ACCEPTED" : reason.c_str());
    }
  EXPECT_EQ(rejected, static_cast<int>((last + 1) * last / 2 - 1));
}

}  // namespace
}  // namespace plugslam
