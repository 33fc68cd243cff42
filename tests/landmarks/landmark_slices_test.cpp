// The landmark cue's slices on synthetic scenes: association by projection and descriptor, the
// Multi-Aligner recovering a known motion (3D, and 2D through a camera mount), and the landmark
// map's merge (tracks, refinement, pruning).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "plugslam/geometry.h"
#include "plugslam/landmarks/landmark_slices.h"
#include "plugslam/landmarks/point_registration.h"
#include "plugslam/multi_aligner.h"
#include "plugslam/slice_check.h"

namespace plugslam {
namespace {

struct World {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<uint8_t, 32>> descriptors;
};

World makeWorld(std::mt19937& rng, int n) {
  // Points in front of a camera looking along +z from near the origin, 4..40 m away.
  World w;
  std::uniform_real_distribution<double> x(-15, 15), y(-4, 4), z(4, 40);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int i = 0; i < n; ++i) {
    w.points.emplace_back(x(rng), y(rng), z(rng));
    std::array<uint8_t, 32> d;
    for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
    w.descriptors.push_back(d);
  }
  return w;
}

// fx, fy, cx, cy [px], baseline [m].
PinholeCamera camera() { return {700, 700, 620, 188, 0.54}; }

// What a stereo camera at `camera_in_world` measures: projections with pixel noise, disparity
// noise, and a fraction of keypoints whose descriptor belongs to a different point (outliers).
FeatureSet observe(const World& w, const Eigen::Isometry3d& camera_in_world,
                   const Eigen::Isometry3d& mount, std::mt19937& rng, double sigma_px,
                   double sigma_d, double outliers) {
  FeatureSet f;
  f.camera = camera();
  f.width = 1241;
  f.height = 376;
  f.mount = mount;
  std::normal_distribution<double> npx(0, sigma_px), nd(0, sigma_d);
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<size_t> any(0, w.points.size() - 1);
  const Eigen::Isometry3d to_cam = camera_in_world.inverse();
  for (size_t i = 0; i < w.points.size(); ++i) {
    const Eigen::Vector3d pc = to_cam * w.points[i];
    if (pc.z() < 1) continue;
    const double u = f.camera.fx * pc.x() / pc.z() + f.camera.cx;
    const double v = f.camera.fy * pc.y() / pc.z() + f.camera.cy;
    if (u < 0 || v < 0 || u > f.width - 1 || v > f.height - 1) continue;
    const double d = f.camera.fx * f.camera.baseline / pc.z();
    const uint8_t* desc = w.descriptors[unit(rng) < outliers ? any(rng) : i].data();
    f.pushStereo(Eigen::Vector2d(u + npx(rng), v + npx(rng)), std::max(sigma_px, 0.5),
                 d + nd(rng), std::max(sigma_d, 0.2), desc, 0x808080);
  }
  return f;
}

TEST(FeatureGrid, PairsEachLandmarkWithTheMatchingDescriptorNearItsProjection) {
  std::mt19937 rng(1);
  const World w = makeWorld(rng, 300);
  const FeatureSet f = observe(w, Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(),
                               rng, 0.0, 0.0, 0.0);
  LandmarkMap map;
  for (size_t i = 0; i < w.points.size(); ++i)
    map.push(w.points[i], Eigen::Matrix3d::Identity(), i, w.descriptors[i].data(), 0, 0);
  FeatureGrid grid;
  grid.build(f);
  std::vector<LandmarkMatch> matches;
  std::vector<bool> visible;
  AssociationOptions o;
  o.radius = 3;
  // Shifted by 1 px: the radius still covers the true keypoint.
  Eigen::Isometry3d cam = Eigen::Isometry3d::Identity();
  cam.translation().x() = 0.01;
  grid.associate(map, cam, o, matches, &visible);
  ASSERT_GT(matches.size(), f.size() * 9 / 10);
  for (const auto& m : matches) {
    EXPECT_EQ(m.distance, 0);
    EXPECT_LT((f.pixels[m.feature] - f.pixels[m.feature]).norm(), 1e-9);
    EXPECT_EQ(std::memcmp(f.descriptor(m.feature), map.descriptor(m.landmark), 32), 0);
  }
  // A descriptor check rejects landmarks whose descriptor is far from every nearby keypoint.
  for (size_t j = 0; j < map.size(); ++j)
    for (int k = 0; k < 32; ++k) map.descriptor(j)[k] ^= 0xff;
  grid.associate(map, cam, o, matches);
  EXPECT_TRUE(matches.empty());
}

// With pyramid keypoints a landmark is expected at the scale its reference distance predicts:
// one seen at full resolution from 4 m is expected at scale 2 from 2 m, and only a keypoint of
// about that scale (with the same descriptor, at the same place) is its match; the search
// radius grows with the scale.
TEST(FeatureGrid, PairsALandmarkOnlyWithAKeypointOfItsPredictedScale) {
  EXPECT_DOUBLE_EQ(predictedScale(4.0, 2.0, 3.6), 2.0);
  EXPECT_DOUBLE_EQ(predictedScale(4.0, 8.0, 3.6), 1.0);   // farther: the finest level
  EXPECT_DOUBLE_EQ(predictedScale(40.0, 2.0, 3.6), 3.6);  // nearer than searched: the coarsest
  EXPECT_DOUBLE_EQ(predictedScale(0.0, 2.0, 3.6), 1.0);   // unknown
  FeatureSet f;
  f.camera = camera();
  f.width = 1241;
  f.height = 376;
  f.max_scale = 3.6;
  std::array<uint8_t, 32> d{};
  d.fill(0x5a);
  const Eigen::Vector3d point(0, 0, 2);  // on the optical axis, 2 m ahead: pixel (cx, cy)
  const Eigen::Vector2d centre(f.camera.cx, f.camera.cy);
  // Same place, same descriptor, full resolution: the wrong scale.
  f.pushStereo(centre, 1.0, 0, 0, d.data(), 0, 1.0);
  LandmarkMap map;
  map.push(point, Eigen::Matrix3d::Identity(), 1, d.data(), 0, 0, 4.0);
  FeatureGrid grid;
  grid.build(f);
  AssociationOptions o;
  o.radius = 3;
  o.scale_tolerance = 1.5;
  std::vector<LandmarkMatch> matches;
  grid.associate(map, Eigen::Isometry3d::Identity(), o, matches);
  EXPECT_TRUE(matches.empty());
  // Scale not checked: it matches.
  o.scale_tolerance = 0;
  grid.associate(map, Eigen::Isometry3d::Identity(), o, matches);
  EXPECT_EQ(matches.size(), 1u);
  // A keypoint of scale 2.07 (four levels of 1.2) 5 px off: inside the 3 px radius times 2.
  f.clear();
  f.pushStereo(centre + Eigen::Vector2d(5, 0), 2.07, 0, 0, d.data(), 0, 2.07);
  grid.build(f);
  o.scale_tolerance = 1.5;
  grid.associate(map, Eigen::Isometry3d::Identity(), o, matches);
  ASSERT_EQ(matches.size(), 1u);
  EXPECT_EQ(matches[0].feature, 0);
  // Without a pyramid (max_scale 1) every keypoint is expected at full resolution.
  f.clear();
  f.max_scale = 1.0;
  f.pushStereo(centre, 1.0, 0, 0, d.data(), 0, 1.0);
  grid.build(f);
  grid.associate(map, Eigen::Isometry3d::Identity(), o, matches);
  EXPECT_EQ(matches.size(), 1u);
}

// A scene whose landmarks are `reference`'s keypoints seen from `pose`, as a tracker's
// LandmarkMapSlice makes it.
template <class S>
PropertyContainer sceneOf(const FeatureSet& reference, const typename S::Pose& pose) {
  PropertyContainer scene;
  Frame ref;
  ref.measurement.set<FeatureSet>("features", reference);
  LandmarkMapSlice<S> merger;
  merger.configure();
  merger.merge(ref, scene, pose);
  return scene;
}

template <class S>
AlignResult<S> alignOnce(const FeatureSet& reference, const FeatureSet& current,
                         const typename S::Pose& reference_pose, const typename S::Pose& guess,
                         ReprojectionSlice<S>** slice_out = nullptr,
                         bool landmark_uncertainty = false) {
  const PropertyContainer scene = sceneOf<S>(reference, reference_pose);
  EXPECT_EQ(scene.get<LandmarkMap>("landmarks").size(), reference.size());
  MultiAligner<S> aligner;
  auto slice = std::make_shared<ReprojectionSlice<S>>();
  slice->landmark_uncertainty = landmark_uncertainty;
  slice->configure();
  if (slice_out) *slice_out = slice.get();
  aligner.slices.assign(slice);
  aligner.configure();
  Frame frame;
  frame.measurement.set<FeatureSet>("features", current);
  return aligner.align(frame, scene, AlignContext<S>{guess, guess});
}

TEST(ReprojectionSlice, RecoversAKnownMotionIn3D) {
  std::mt19937 rng(2);
  const World w = makeWorld(rng, 1500);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  Vector6d motion;
  motion << 0.1, -0.05, 1.0, 0.01, 0.03, -0.005;  // a car's frame at 10 Hz, 10 m/s
  const Eigen::Isometry3d truth = se3(motion);
  // Exact data: the solution is the truth to rounding.
  {
    const FeatureSet a = observe(w, id, id, rng, 0, 0, 0);
    const FeatureSet b = observe(w, truth, id, rng, 0, 0, 0);
    const auto r = alignOnce<Space3D>(a, b, id, id);
    ASSERT_TRUE(r.valid);
    EXPECT_LT(toVector(truth.inverse() * r.pose).norm(), 1e-6);
  }
  // 1 px / 0.3 px noise and 10 % wrong descriptors: the robust kernel keeps the error small.
  {
    const FeatureSet a = observe(w, id, id, rng, 1.0, 0.3, 0.1);
    const FeatureSet b = observe(w, truth, id, rng, 1.0, 0.3, 0.1);
    const auto r = alignOnce<Space3D>(a, b, id, id);
    ASSERT_TRUE(r.valid);
    const Vector6d err = toVector(truth.inverse() * r.pose);
    // Measured 1.2 cm / 0.04 deg at seed 2 (noisy map from one frame); 5 cm, 0.3 deg fail a
    // broken Jacobian or a lost association.
    EXPECT_LT(err.head<3>().norm(), 0.05);
    EXPECT_LT(err.tail<3>().norm(), 0.3 * M_PI / 180);
    // 10 % outliers, and the map's own noise doubles each residual's variance, so the 95 %
    // chi-square band holds fewer: measured 0.72; a broken association falls far below 0.6.
    EXPECT_GT(r.inlierRatio(), 0.6);
  }
}

// landmark_uncertainty: each residual's covariance is the keypoint's plus the landmark's
// projected into the image. The map of one noisy frame then weighs what it is worth: the 95 %
// band holds the inliers it should (90 % correct descriptors), and the pose is no worse.
TEST(ReprojectionSlice, WeighsEachResidualByTheLandmarksOwnUncertainty) {
  std::mt19937 rng(2);
  const World w = makeWorld(rng, 1500);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  Vector6d motion;
  motion << 0.1, -0.05, 1.0, 0.01, 0.03, -0.005;
  const Eigen::Isometry3d truth = se3(motion);
  const FeatureSet a = observe(w, id, id, rng, 1.0, 0.3, 0.1);
  const FeatureSet b = observe(w, truth, id, rng, 1.0, 0.3, 0.1);
  const auto plain = alignOnce<Space3D>(a, b, id, id);
  const auto weighed = alignOnce<Space3D>(a, b, id, id, nullptr, true);
  ASSERT_TRUE(plain.valid);
  ASSERT_TRUE(weighed.valid);
  const Vector6d e_plain = toVector(truth.inverse() * plain.pose);
  const Vector6d e_weighed = toVector(truth.inverse() * weighed.pose);
  std::printf("inlier ratio %.3f -> %.3f; error %.4f m %.4f deg -> %.4f m %.4f deg\n",
              plain.inlierRatio(), weighed.inlierRatio(), e_plain.head<3>().norm(),
              e_plain.tail<3>().norm() * 180 / M_PI, e_weighed.head<3>().norm(),
              e_weighed.tail<3>().norm() * 180 / M_PI);
  // Without the landmark's covariance the band holds 0.72 (measured, the test above); with it
  // the residuals are whitened by their true spread, so about 0.95 of the 90 % correct ones.
  EXPECT_GT(weighed.inlierRatio(), 0.8);
  EXPECT_GT(weighed.inlierRatio(), plain.inlierRatio() + 0.05);
  EXPECT_LT(e_weighed.head<3>().norm(), 0.05);
  EXPECT_LT(e_weighed.tail<3>().norm(), 0.3 * M_PI / 180);
}

TEST(ReprojectionSlice, AlignsAPlanarRobotThroughTheCameraMount) {
  // A ground robot (x forward, z up) with a forward camera 1.2 m up: the same factors constrain
  // its (x, y, theta) in a 2D pipeline.
  std::mt19937 rng(4);
  World w = makeWorld(rng, 1500);
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
  mount.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  mount.translation() << 0.3, 0.0, 1.2;
  // The world's points are generated in the camera frame at the start: move them to the world.
  for (auto& p : w.points) p = mount * p;
  const Eigen::Isometry2d start = Eigen::Isometry2d::Identity();
  const Eigen::Isometry2d truth = se2(0.8, 0.1, 0.05);
  const FeatureSet a = observe(w, Space2D::to3D(start) * mount, mount, rng, 0.5, 0.2, 0.05);
  const FeatureSet b = observe(w, Space2D::to3D(truth) * mount, mount, rng, 0.5, 0.2, 0.05);
  const auto r = alignOnce<Space2D>(a, b, start, start);
  ASSERT_TRUE(r.valid);
  const Eigen::Vector3d err = toVector(Eigen::Isometry2d(truth.inverse() * r.pose));
  // Measured under 1 cm and 0.01 deg; 3 cm / 0.2 deg catch a wrong tangent embedding.
  EXPECT_LT(err.head<2>().norm(), 0.03);
  EXPECT_LT(std::abs(err.z()), 0.2 * M_PI / 180);
}

// The slice's factors as the aligner sees them, at `at`, against a map made from `reference`.
template <class S>
SliceJacobianCheck checkReprojectionJacobians(const FeatureSet& reference,
                                              const FeatureSet& current,
                                              const typename S::Pose& at) {
  const PropertyContainer scene = sceneOf<S>(reference, S::Pose::Identity());
  ReprojectionSlice<S> slice;
  slice.configure();
  Frame frame;
  frame.measurement.set<FeatureSet>("features", current);
  EXPECT_TRUE(slice.bind(frame, scene, AlignContext<S>{at, at}));
  slice.associate(at);
  EXPECT_GT(slice.matches().size(), 100u);
  return checkSliceJacobians(slice, at);
}

// Every factor the slice adds passes the SDK's Jacobian check (central differences through the
// pose variable's oplus, the aligner's boxplus): in 3D, and in 2D through a tilted mount, where
// the Jacobian is the 3D one restricted to (x, y, theta); with and without depth.
TEST(ReprojectionSlice, EveryFactorPassesTheJacobianCheck) {
  std::mt19937 rng(6);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  {
    const World w = makeWorld(rng, 600);
    Vector6d motion;
    motion << 0.1, -0.05, 1.0, 0.01, 0.03, -0.005;
    const FeatureSet a = observe(w, id, id, rng, 0.5, 0.2, 0.0);
    FeatureSet b = observe(w, se3(motion), id, rng, 0.5, 0.2, 0.0);
    for (size_t i = 0; i < b.size(); i += 2) b.inverse_depth[i] = 0;  // half without depth
    // Away from the solution, so that the errors are not zero.
    motion << 0.12, -0.04, 0.97, 0.012, 0.028, -0.004;
    const SliceJacobianCheck r = checkReprojectionJacobians<Space3D>(a, b, se3(motion));
    EXPECT_GT(r.factors, 100u);
    EXPECT_TRUE(r.ok()) << r;
  }
  {
    World w = makeWorld(rng, 600);
    Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
    mount.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    mount.translation() << 0.3, 0.1, 1.2;
    for (auto& p : w.points) p = mount * p;
    const FeatureSet a = observe(w, mount, mount, rng, 0.5, 0.2, 0.0);
    const Eigen::Isometry3d camera_in_world = Space2D::to3D(se2(0.8, 0.1, 0.05)) * mount;
    FeatureSet b = observe(w, camera_in_world, mount, rng, 0.5, 0.2, 0.0);
    for (size_t i = 1; i < b.size(); i += 2) b.inverse_depth[i] = 0;
    const SliceJacobianCheck r = checkReprojectionJacobians<Space2D>(a, b, se2(0.78, 0.11, 0.052));
    EXPECT_GT(r.factors, 100u);
    EXPECT_TRUE(r.ok()) << r;
  }
}

TEST(LandmarkMapSlice, KeepsTracksRefinesAndPrunes) {
  std::mt19937 rng(5);
  const World w = makeWorld(rng, 400);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  LandmarkMapSlice<Space3D> slice;
  slice.configure();
  PropertyContainer scene;
  double first_error = 0, last_error = 0;
  std::vector<uint64_t> first_ids;
  for (int k = 0; k < 6; ++k) {
    Frame frame;
    frame.seq = static_cast<uint64_t>(k);
    frame.measurement.set<FeatureSet>("features", observe(w, id, id, rng, 0.5, 0.5, 0.0));
    slice.merge(frame, scene, id);
    const LandmarkMap& m = scene.get<LandmarkMap>("landmarks");
    double err = 0;
    for (size_t j = 0; j < m.size(); ++j)
      err += (m.positions[j] - w.points[static_cast<size_t>(
                                  std::find_if(w.descriptors.begin(), w.descriptors.end(),
                                               [&](const auto& d) {
                                                 return std::memcmp(d.data(), m.descriptor(j),
                                                                    32) == 0;
                                               }) -
                                  w.descriptors.begin())])
                 .norm();
    err /= static_cast<double>(m.size());
    if (k == 0) {
      first_error = err;
      first_ids = m.ids;
    } else {
      // Every keypoint is matched again: the same tracks, one more observation each.
      EXPECT_EQ(m.ids, first_ids);
      EXPECT_EQ(slice.lastCreated(), 0u);
      for (uint32_t o : m.observations) EXPECT_EQ(o, static_cast<uint32_t>(k + 1));
    }
    last_error = err;
  }
  // Fusing six independent observations shrinks the error (about 1/sqrt(6) = 0.41 in theory).
  EXPECT_LT(last_error, 0.6 * first_error);

  // A landmark that projects into the view but is never found again is pruned after
  // prune_after frames; here the camera sees a world whose descriptors all changed.
  World other = w;
  for (auto& d : other.descriptors)
    for (auto& b : d) b = static_cast<uint8_t>(~b);
  const size_t before = scene.get<LandmarkMap>("landmarks").size();
  for (int k = 0; k < 20; ++k) {
    Frame frame;
    frame.seq = static_cast<uint64_t>(10 + k);
    FeatureSet f = observe(other, id, id, rng, 0.5, 0.5, 0.0);
    // No new landmarks: keep only keypoints without depth.
    std::fill(f.inverse_depth.begin(), f.inverse_depth.end(), 0.0);
    frame.measurement.set<FeatureSet>("features", f);
    slice.merge(frame, scene, id);
  }
  EXPECT_GT(before, 0u);
  EXPECT_EQ(scene.get<LandmarkMap>("landmarks").size(), 0u);
}

// A wide motion: 2.5 m sideways and forward with a 25 degree turn, far beyond what projective
// association from an identity prediction bridges (the 20 px first radius).
struct WidePair {
  Eigen::Isometry3d truth;  // camera b in camera a's frame
  FeatureSet a, b;
};

// Two stereo views of one random world across that motion (1 px / 0.3 px noise, a fraction
// `outliers` of the keypoints carrying another point's descriptor).
WidePair widePair(unsigned seed, double outliers) {
  std::mt19937 rng(seed);
  const World w = makeWorld(rng, 1500);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  Vector6d motion;
  motion << 1.5, 0.1, 2.0, 0.02, 25.0 * M_PI / 180, 0.01;
  WidePair p;
  p.truth = se3(motion);
  p.a = observe(w, id, id, rng, 1.0, 0.3, outliers);
  p.b = observe(w, p.truth, id, rng, 1.0, 0.3, outliers);
  return p;
}

TEST(PointRegistration, FindsAWideMotionWithoutAPrior) {
  // 30 % of the keypoints carry another point's descriptor.
  const WidePair pair = widePair(7, 0.3);
  const Eigen::Isometry3d& truth = pair.truth;
  const FeatureSet &a = pair.a, &b = pair.b;
  // b's points into a's frame: a <- b is the motion itself.
  const PointRegistration r = registerPoints(describedPoints(b), describedPoints(a));
  ASSERT_TRUE(r.valid);
  const Vector6d err = toVector(truth.inverse() * r.target_from_source);
  std::printf("registration: %zu matches, %zu inliers, %d samples, error %.4f m %.4f deg\n",
              r.matches, r.inliers.size(), r.iterations, err.head<3>().norm(),
              err.tail<3>().norm() * 180 / M_PI);
  // Bounds: measured 8.4 mm / 0.047 deg (455 matches, 311 inliers, 28 samples); 10 cm and
  // 0.5 deg still fail a wrong sample or a broken fit (a wrong one is metres off). Stereo depth
  // at 4-40 m is the noise here.
  EXPECT_LT(err.head<3>().norm(), 0.10);
  EXPECT_LT(err.tail<3>().norm(), 0.5 * M_PI / 180);
  // Inliers are true pairs, the same world point seen twice (an outlier keypoint carries another
  // point's descriptor, so it matches that point's keypoint and RANSAC must drop the pair): at the
  // true motion a true pair lies within chi-square 99.9 % (3 dof) of both covariances, a wrong
  // one metres away.
  const DescribedPoints da = describedPoints(a), db = describedPoints(b);
  size_t wrong = 0;
  for (const PointMatch& m : r.inliers) {
    const size_t ia = static_cast<size_t>(m.target), ib = static_cast<size_t>(m.source);
    const Eigen::Vector3d d = da.points[ia] - truth * db.points[ib];
    const Eigen::Matrix3d c =
        da.covariances[ia] + truth.linear() * db.covariances[ib] * truth.linear().transpose();
    if (d.dot(c.ldlt().solve(d)) > 16.27) ++wrong;
  }
  EXPECT_LT(wrong, r.inliers.size() / 50 + 1);
  EXPECT_GT(r.inliers.size(), 100u);
  // Unrelated descriptors on both sides: nothing to register.
  FeatureSet c = b;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& d : c.descriptors) d = static_cast<uint8_t>(byte(rng));
  EXPECT_FALSE(registerPoints(describedPoints(c), describedPoints(a)).valid);
}

TEST(ReprojectionSlice, RecoversAWideMotionByDescriptorMatching) {
  const WidePair pair = widePair(8, 0.1);
  const Eigen::Isometry3d& truth = pair.truth;
  const FeatureSet &a = pair.a, &b = pair.b;
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  const PropertyContainer scene = sceneOf<Space3D>(a, id);
  for (bool recover : {false, true}) {
    MultiAligner<Space3D> aligner;
    auto slice = std::make_shared<ReprojectionSlice<Space3D>>();
    slice->configure();
    aligner.slices.assign(slice);
    aligner.relocalise.set(recover);
    aligner.configure();
    Frame frame;
    frame.measurement.set<FeatureSet>("features", b);
    const auto r = aligner.align(frame, scene, AlignContext<Space3D>{id, id});
    if (!recover) {
      // From the identity prediction the projective association finds no consistent pairs.
      EXPECT_FALSE(r.valid);
      continue;
    }
    ASSERT_TRUE(r.valid);
    // The reprojection solve refines the RANSAC pose: measured 9.8 mm / 0.033 deg (393
    // inliers), bounds as in RecoversAKnownMotionIn3D (5 cm, 0.3 deg).
    const Vector6d err = toVector(truth.inverse() * r.pose);
    std::printf("recovered and refined: %zu inliers, error %.4f m %.4f deg\n", r.inliers,
                err.head<3>().norm(), err.tail<3>().norm() * 180 / M_PI);
    EXPECT_LT(err.head<3>().norm(), 0.05);
    EXPECT_LT(err.tail<3>().norm(), 0.3 * M_PI / 180);
    double recoveries = -1;
    for (const Statistic& st : slice->statistics())
      if (st.name == "recoveries") recoveries = st.value;
    EXPECT_EQ(recoveries, 1.0);
  }
}

TEST(LandmarkMapSlice, HandsOverWhatTheSplittingFrameSawInTheNewMapsFrame) {
  const WidePair pair = widePair(9, 0.0);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  PropertyContainer scene;
  LandmarkMapSlice<Space3D> merger;
  merger.configure();
  Frame first;
  first.seq = 0;
  first.measurement.set<FeatureSet>("features", pair.a);
  merger.merge(first, scene, id);
  Frame second;
  second.seq = 1;
  second.measurement.set<FeatureSet>("features", pair.b);
  merger.merge(second, scene, pair.truth);  // at its true pose: matches a's landmarks in view
  const LandmarkMap& old = scene.get<LandmarkMap>("landmarks");
  size_t seen = 0;
  for (uint64_t s : old.last_seen) seen += s == 1;
  ASSERT_GT(seen, 100u);
  ASSERT_LT(seen, old.size());  // some of a's landmarks are out of b's view
  PropertyContainer next;
  merger.handOver(scene, next, pair.truth, 1);
  const LandmarkMap& carried = next.get<LandmarkMap>("landmarks");
  ASSERT_EQ(carried.size(), seen);
  carried.checkConsistent();
  size_t k = 0;
  for (size_t j = 0; j < old.size(); ++j) {
    if (old.last_seen[j] != 1) continue;
    // Same track, same counters, the position in the new map's frame (origin = b's pose).
    EXPECT_EQ(carried.ids[k], old.ids[j]);
    EXPECT_EQ(carried.observations[k], old.observations[j]);
    EXPECT_LT((carried.positions[k] - pair.truth.inverse() * old.positions[j]).norm(), 1e-9);
    EXPECT_NEAR(carried.covariances[k].trace(), old.covariances[j].trace(), 1e-9);
    ++k;
  }
}

}  // namespace
}  // namespace plugslam
