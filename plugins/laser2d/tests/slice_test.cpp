// Aligner slices: offset recovery on synthetic scans, Jacobians against the SDK factors, two
// scanners in one Multi-Aligner, and PointCloud2D through the archives.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "plugslam/multi_aligner.h"
#include "plugslam/property_container.h"
#include "plugslam/slice_check.h"
#include "plugslam/solver/jacobian_check.h"
#include "plugslam/solver/registration_factors.h"
#include "plugslam/value_types.h"
#include "scan_preprocessor.h"
#include "scan_slices.h"
#include "synthetic.h"
#include "temp_dir.h"

namespace plugslam::laser2d {
namespace {

PointCloud2D cloudOf(const LaserScan& scan, double normal_radius = 0.5, int neighbors = 3) {
  ScanPreprocessor pre;
  pre.normal_radius = normal_radius;
  pre.normal_neighbors = neighbors;
  pre.configure();
  PointCloud2D cloud;
  pre.convert(scan, cloud);
  return cloud;
}

double rotationError(const SE2& a, const SE2& b) {
  return std::abs(angleOf((a.inverse() * b).linear()));
}

// The scan of `world` from `at` as the frame's measurement, and the one from `scene_at` as the
// scene, both as "front".
template <class World>
void scanPair(const World& world, const SE2& at, const SE2& scene_at, const test::ScanSpec& spec,
              Frame& frame, PropertyContainer& scene) {
  frame.measurement.set("front", cloudOf(test::castScan(world, at, spec)));
  scene.set("front", cloudOf(test::castScan(world, scene_at, spec)));
}

template <class SliceT>
AlignResult<Space2D> alignRoom(const SE2& offset, const std::string& association,
                               SliceT** slice_out = nullptr) {
  const auto world = test::room(8, 6);
  const SE2 a = se2(3.0, 2.0, 0.2);
  Frame frame;
  PropertyContainer scene;
  scanPair(world, a * offset, a, test::ScanSpec{}, frame, scene);

  MultiAligner<Space2D> aligner;
  auto slice = std::make_shared<SliceT>();
  slice->max_distance = 1.0;
  slice->association = association;
  slice->configure();
  aligner.slices.assign(slice);
  aligner.outer_iterations = 40;
  if (slice_out) *slice_out = slice.get();
  return aligner.align(frame, scene, {SE2::Identity(), SE2::Identity()});
}

TEST(PointToLineSlice, RecoversAKnownOffsetInARoom) {
  const SE2 offset = se2(0.3, -0.2, 0.1);
  const auto r = alignRoom<PointToLineSlice>(offset, "kdtree");
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.converged);
  EXPECT_LT((r.pose.translation() - offset.translation()).norm(), 1e-3);
  EXPECT_LT(rotationError(r.pose, offset), 0.1 * M_PI / 180);
  EXPECT_GT(r.inlierRatio(), 0.9);
}

TEST(MultiAligner, TheSearchRecoversAHeadingErrorTheCovarianceAllows) {
  // A 0.6 rad heading error moves the far walls of a 40 x 30 m hall by metres: with a 0.3 m
  // gate the solve from the guess finds too few pairs. With a covariance that allows it
  // (0.3 rad sigma: a 0.9 rad window), the correlative search finds the heading and the solve
  // converges to the truth.
  const auto world = test::room(40, 30);
  const SE2 a = se2(15.0, 12.0, 0.0);
  const SE2 offset = se2(0.1, 0.05, 0.6);
  test::ScanSpec spec;
  spec.range_max = 60;
  Frame frame;
  PropertyContainer scene;
  scanPair(world, a * offset, a, spec, frame, scene);
  MultiAligner<Space2D> aligner;
  auto slice = std::make_shared<PointToLineSlice>();
  slice->max_distance = 0.3;
  slice->configure();
  aligner.slices.assign(slice);
  aligner.min_inliers = 100;
  aligner.configure();
  const auto plain = aligner.align(frame, scene, {SE2::Identity(), SE2::Identity()});
  EXPECT_FALSE(plain.valid && rotationError(plain.pose, offset) < 0.01);

  AlignContext<Space2D> context{SE2::Identity(), SE2::Identity()};
  context.covariance = Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.3 * 0.3).asDiagonal();
  const auto r = aligner.align(frame, scene, context);
  EXPECT_TRUE(r.valid);
  EXPECT_TRUE(r.searched);
  EXPECT_LT((r.pose.translation() - offset.translation()).norm(), 1e-3);
  EXPECT_LT(rotationError(r.pose, offset), 0.1 * M_PI / 180);

  aligner.max_window = std::vector<double>{0.1};
  EXPECT_THROW(aligner.configure(), ParamError);
}

TEST(PointToLineSlice, ProjectiveAssociationRecoversTheOffset) {
  const SE2 offset = se2(0.2, 0.1, -0.08);
  const auto r = alignRoom<PointToLineSlice>(offset, "projective");
  EXPECT_TRUE(r.valid);
  EXPECT_LT((r.pose.translation() - offset.translation()).norm(), 1e-3);
  EXPECT_LT(rotationError(r.pose, offset), 0.1 * M_PI / 180);
}

TEST(PointToPointSlice, RecoversAKnownOffsetInARoom) {
  // Point-to-point pairs different samples of the same wall: accurate to about the beam spacing.
  const SE2 offset = se2(0.3, -0.2, 0.1);
  const auto r = alignRoom<PointToPointSlice>(offset, "kdtree");
  EXPECT_TRUE(r.valid);
  EXPECT_LT((r.pose.translation() - offset.translation()).norm(), 0.02);
  EXPECT_LT(rotationError(r.pose, offset), 0.5 * M_PI / 180);
}

TEST(PointToLineSlice, UnchangedSceneKeepsItsKdTree) {
  const auto world = test::room(8, 6);
  test::ScanSpec spec;
  PropertyContainer scene;
  scene.set("front", cloudOf(test::castScan(world, se2(3, 2, 0), spec)));
  PointToLineSlice slice;
  slice.configure();
  for (int k = 0; k < 3; ++k) {
    Frame frame;
    frame.measurement.set("front", cloudOf(test::castScan(world, se2(3.1 + 0.05 * k, 2, 0), spec)));
    ASSERT_TRUE(slice.bind(frame, scene, {}));
  }
  EXPECT_EQ(slice.treeBuilds(), 1u);
  scene.get<PointCloud2D>("front").touch();
  Frame frame;
  frame.measurement.set("front", cloudOf(test::castScan(world, se2(3, 2, 0), spec)));
  ASSERT_TRUE(slice.bind(frame, scene, {}));
  EXPECT_EQ(slice.treeBuilds(), 2u);
  // A missing cue: the slice sits the frame out.
  Frame empty;
  EXPECT_FALSE(slice.bind(empty, scene, {}));
}

TEST(PointToLineSlice, PointsPastTheEndOfASurfaceAreNotPaired) {
  // A wall from x = 0 to 1 m (points every 5 cm, normals +y) and three measured points: on the
  // wall, 0.15 m past its end and 0.4 m past it (a door gap). The last is within the 0.5 m gate
  // of the wall's end point, but point-to-line would extrapolate the wall to it.
  PointCloud2D wall, measured;
  for (int k = 0; k <= 20; ++k) wall.push({0.05 * k, 0.0}, {0.0, 1.0}, 1.0);
  wall.touch();
  measured.push({0.52, 0.03}, {0.0, 1.0}, 1.0);
  measured.push({1.15, 0.03}, {0.0, 1.0}, 1.0);
  measured.push({1.40, 0.03}, {0.0, 1.0}, 1.0);
  measured.touch();
  PropertyContainer scene;
  scene.set("front", wall);
  Frame frame;
  frame.measurement.set("front", measured);
  // (k-d tree association: the projective one only pairs points of nearly the same bearing.)
  PointToLineSlice slice;
  slice.configure();
  ASSERT_TRUE(slice.bind(frame, scene, {}));
  slice.associate(SE2::Identity());
  std::vector<int> paired;
  for (const auto& [i, j] : slice.pairs()) paired.push_back(i);
  EXPECT_EQ(paired, (std::vector<int>{0, 1}));
  slice.max_tangential = 0.0;  // off: the point in the gap is paired too
  ASSERT_TRUE(slice.bind(frame, scene, {}));
  slice.associate(SE2::Identity());
  EXPECT_EQ(slice.pairs().size(), 3u);
}

// A scan of the room as the measurement and one 0.1 m, 0.05 rad away as the scene ("front").
void offsetScans(Frame& frame, PropertyContainer& scene) {
  scanPair(test::room(8, 6), se2(3.1, 2, 0.05), se2(3, 2, 0), test::ScanSpec{}, frame, scene);
}

// Every factor the laser slices add passes the SDK's Jacobian check (central differences through
// the pose variable's oplus, which is the aligner's boxplus), around and away from the solution.
template <class SliceT>
void checkEveryFactor() {
  Frame frame;
  PropertyContainer scene;
  offsetScans(frame, scene);
  SliceT slice;
  slice.range_sigma = 0.01;  // per-pair information, as the CARMEN configs use
  slice.configure();
  ASSERT_TRUE(slice.bind(frame, scene, {}));
  for (const SE2& t : {SE2::Identity(), se2(0.08, 0.01, 0.04), se2(-0.2, 0.15, -0.1)}) {
    slice.associate(t);
    const SliceJacobianCheck r = checkSliceJacobians(slice, t);
    EXPECT_GT(r.factors, 100u);
    EXPECT_EQ(r.factors, slice.pairs().size());
    EXPECT_TRUE(r.ok()) << r;
    // Every measured point is a candidate, paired or not: the base of the cue's overlap.
    NormalEquations<Space2D> eq;
    slice.linearize(t, eq);
    EXPECT_EQ(eq.candidates, frame.measurement.get<PointCloud2D>("front").size());
  }
}

TEST(PointToLineSlice, EveryFactorPassesTheJacobianCheck) { checkEveryFactor<PointToLineSlice>(); }

TEST(PointToPointSlice, EveryFactorPassesTheJacobianCheck) {
  checkEveryFactor<PointToPointSlice>();
}

TEST(PointToLineSlice, NormalEquationsAreTheSumOfTheFactors) {
  Frame frame;
  PropertyContainer scene;
  offsetScans(frame, scene);
  PointToLineSlice slice;
  slice.kernel = "none";
  slice.sigma = 0.1;
  slice.configure();
  const SE2 t = se2(0.08, 0.01, 0.04);
  ASSERT_TRUE(slice.bind(frame, scene, {}));
  slice.associate(t);
  ASSERT_GT(slice.pairs().size(), 100u);
  NormalEquations<Space2D> eq;
  slice.linearize(t, eq);

  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  double chi2 = 0;
  const auto& m = frame.measurement.get<PointCloud2D>("front");
  const auto& s = scene.get<PointCloud2D>("front");
  for (const auto& [i, j] : slice.pairs()) {
    VariableSE2 var(0, t);
    PointToLineFactor2D f(&var, m.points[i], s.points[j], s.normals[j]);
    f.setInformation(PointToLineFactor2D::InformationMatrix::Constant(1.0 / (0.1 * 0.1)));
    PointToLineFactor2D::ErrorVector e;
    PointToLineFactor2D::JacobianMatrix jac;
    f.errorAndJacobian(e, jac);
    h += jac.transpose() * f.information() * jac;
    b += jac.transpose() * f.information() * e;
    chi2 += f.chi2();
  }
  EXPECT_LT((eq.H - h).cwiseAbs().maxCoeff(), 1e-9 * h.cwiseAbs().maxCoeff());
  EXPECT_LT((eq.b - b).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, b.cwiseAbs().maxCoeff()));
  EXPECT_NEAR(eq.chi2, chi2, 1e-9 * chi2);
  EXPECT_EQ(eq.factors, slice.pairs().size());
}

TEST(PointToLineSlice, RangeSigmaWeighsEachPairByItsRange) {
  // Far points in a big room: with range_sigma each pair weighs 1 / (sigma^2 + (k r)^2), r the
  // measured point's distance from the sensor; without it every pair weighs 1 / sigma^2.
  const auto world = test::room(40, 30);
  test::ScanSpec spec;
  spec.range_max = 60;
  Frame frame;
  frame.measurement.set("front", cloudOf(test::castScan(world, se2(8, 6, 0.05), spec), 2.0));
  PropertyContainer scene;
  scene.set("front", cloudOf(test::castScan(world, se2(8.2, 6, 0), spec), 2.0));
  const SE2 t = se2(-0.15, 0.02, 0.04);
  auto equations = [&](double k) {
    PointToLineSlice slice;
    slice.kernel = "none";
    slice.sigma = 0.05;
    slice.range_sigma = k;
    slice.configure();
    EXPECT_TRUE(slice.bind(frame, scene, {}));
    slice.associate(t);
    NormalEquations<Space2D> eq;
    slice.linearize(t, eq);
    return std::make_pair(eq, slice.pairs());
  };
  const double k = 0.01;
  const auto [weighted, pairs] = equations(k);
  ASSERT_GT(pairs.size(), 100u);
  const auto& m = frame.measurement.get<PointCloud2D>("front");
  const auto& s = scene.get<PointCloud2D>("front");
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  double chi2 = 0, far_range = 0;
  for (const auto& [i, j] : pairs) {
    const double r = (m.points[i] - m.sensor_origin).norm();
    far_range = std::max(far_range, r);
    VariableSE2 var(0, t);
    PointToLineFactor2D f(&var, m.points[i], s.points[j], s.normals[j]);
    f.setInformation(
        PointToLineFactor2D::InformationMatrix::Constant(1.0 / (0.05 * 0.05 + k * k * r * r)));
    PointToLineFactor2D::ErrorVector e;
    PointToLineFactor2D::JacobianMatrix jac;
    f.errorAndJacobian(e, jac);
    h += jac.transpose() * f.information() * jac;
    chi2 += f.chi2();
  }
  ASSERT_GT(far_range, 20.0);  // the room's far walls: sigma_i is several times sigma there
  EXPECT_LT((weighted.H - h).cwiseAbs().maxCoeff(), 1e-9 * h.cwiseAbs().maxCoeff());
  EXPECT_NEAR(weighted.chi2, chi2, 1e-9 * chi2);
  // The same pairs without range_sigma weigh more, so chi2 and information are larger.
  const auto [plain, plain_pairs] = equations(0.0);
  ASSERT_EQ(plain_pairs, pairs);
  EXPECT_GT(plain.chi2, 1.5 * weighted.chi2);
  EXPECT_GT(plain.H.trace(), 1.5 * weighted.H.trace());
}

// A corridor: the front scanner sees the end wall (x observable) with few, noisy beams; the rear
// one, more precise, sees only the side walls (x unobservable). Together they beat either one.
TEST(ScanSlices, TwoScannersInOneAlignerBeatEitherAlone) {
  const auto world = test::corridor(-30.0, 6.0, 1.5);
  test::ScanSpec front, rear;
  front.beams = 61;
  front.fov = M_PI;
  front.noise = 0.03;
  front.mount = se2(0.3, 0.0, 0.0);
  rear.beams = 181;
  rear.fov = M_PI;
  rear.noise = 0.003;
  rear.range_max = 10.0;
  rear.mount = se2(-0.3, 0.0, M_PI);
  const SE2 offset = se2(0.3, 0.1, 0.05);

  auto run = [&](bool use_front, bool use_rear, uint32_t seed) {
    Frame frame;
    PropertyContainer scene;
    front.seed = seed;
    rear.seed = seed + 1000;
    scene.set("front", cloudOf(test::castScan(world, SE2::Identity(), front), 1.0));
    scene.set("rear", cloudOf(test::castScan(world, SE2::Identity(), rear), 1.0, 5));
    front.seed = seed + 1;
    rear.seed = seed + 1001;
    frame.measurement.set("front", cloudOf(test::castScan(world, offset, front), 1.0));
    frame.measurement.set("rear", cloudOf(test::castScan(world, offset, rear), 1.0, 5));
    MultiAligner<Space2D> aligner;
    aligner.outer_iterations = 30;
    for (const char* cue : {"front", "rear"}) {
      if ((std::string(cue) == "front" && !use_front) || (std::string(cue) == "rear" && !use_rear))
        continue;
      auto slice = std::make_shared<PointToLineSlice>();
      slice->measurement = cue;
      slice->scene = cue;
      slice->sigma = std::string(cue) == "front" ? 0.03 : 0.01;  // conservative for the rear
      slice->max_distance = 1.0;
      slice->configure();
      aligner.slices.assign(slice);
    }
    const auto r = aligner.align(frame, scene, {SE2::Identity(), SE2::Identity()});
    return (r.pose.translation() - offset.translation()).norm() + rotationError(r.pose, offset);
  };
  double front_err = 0, rear_err = 0, both_err = 0;
  const int trials = 20;
  for (int k = 0; k < trials; ++k) {
    front_err += run(true, false, 10 * k + 1) / trials;
    rear_err += run(false, true, 10 * k + 1) / trials;
    both_err += run(true, true, 10 * k + 1) / trials;
  }
  RecordProperty("front_err", std::to_string(front_err));
  RecordProperty("rear_err", std::to_string(rear_err));
  RecordProperty("both_err", std::to_string(both_err));
  std::printf("mean error: front %.5f, rear %.5f, both %.5f\n", front_err, rear_err, both_err);
  EXPECT_LT(both_err, front_err);
  EXPECT_LT(both_err, rear_err);
  EXPECT_GT(rear_err, 0.1);  // the rear alone cannot see the offset along the corridor
}

TEST(PointCloud2D, RoundTripsThroughBothArchivesInAContainer) {
  ValueTypes::instance().add<PointCloud2D>("laser2d.PointCloud2D", "laser2d");
  PointCloud2D cloud = cloudOf(test::castScan(test::room(8, 6), se2(3, 2, 0.1), {}));
  cloud.weights[3] = 4.5;
  cloud.sensor_origin = Eigen::Vector2d(0.25, -0.5);
  PropertyContainer c;
  c.set("front", cloud);
  c.set<double>("other", 2.5);
  const plugslam::testing::TempDir tmp("laser2d_cloud");
  const auto dir = tmp.path();
  for (auto format : {ArchiveFormat::kBinary, ArchiveFormat::kText}) {
    const std::string path = (dir / (format == ArchiveFormat::kText ? "c.yaml" : "c.bin")).string();
    saveFile(path, c, format);
    PropertyContainer back;
    loadFile(path, back);
    ASSERT_TRUE(back.holds<PointCloud2D>("front")) << formatName(format);
    const auto& b = back.get<PointCloud2D>("front");
    ASSERT_EQ(b.size(), cloud.size());
    for (size_t i = 0; i < b.size(); ++i) {
      EXPECT_EQ(b.points[i], cloud.points[i]);
      EXPECT_EQ(b.normals[i], cloud.normals[i]);
      EXPECT_EQ(b.weights[i], cloud.weights[i]);
    }
    EXPECT_EQ(b.sensor_origin, cloud.sensor_origin);
    EXPECT_NE(b.revision, 0u);
    EXPECT_EQ(back.get<double>("other"), 2.5);
  }
}

}  // namespace
}  // namespace plugslam::laser2d
