// sim.Simulator3D and sim.SimulatorMixed as sources; real trajectories from PLUGSLAM_DATA.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "plugslam/errors.h"
#include "plugslam/pipeline.h"
#include "plugslam/trajectory.h"
#include "sim3d/mixed.h"
#include "sim3d/renderer.h"
#include "sim3d/trajectory.h"
#include "simulator3d_source.h"
#include "simulator_mixed_source.h"
#include "test_paths.h"

namespace plugslam::sim {
namespace {

namespace fs = std::filesystem;

// The source configured as set, and its first frame (an error when it has none).
template <class Source>
Frame firstFrame(Source& source) {
  source.configure();
  Frame f;
  if (!source.next(f)) throw std::runtime_error("the source gave no frame");
  return f;
}

TEST(Simulator3DSource, RgbdFramesCarryImagesCameraAndGroundTruth) {
  Simulator3DSource source;
  source.duration = 1.0;
  Frame f = firstFrame(source);
  EXPECT_EQ(source.sizeHint(), 31);
  const auto& rgb = f.raw.get<Image>("rgb");
  const auto& depth = f.raw.get<DepthImage>("depth");
  const auto& cam = f.raw.get<CameraInfo>("camera");
  EXPECT_EQ(rgb.width, 640);
  EXPECT_EQ(rgb.channels, 3);
  EXPECT_EQ(depth.height, 480);
  EXPECT_EQ(cam.fx, 525.0);
  EXPECT_EQ(cam.baseline, 0.0);
  EXPECT_TRUE(f.raw.holds<Eigen::Isometry3d>("ground_truth"));
  int frames = 1;
  while (source.next(f)) ++frames;
  EXPECT_EQ(frames, 31);
}

TEST(Simulator3DSource, PipelineRecordsTheThreeDimensionalGroundTruth) {
  Simulator3DSource source;
  source.duration = 0.5;
  source.configure();
  Pipeline pipeline;
  pipeline.configure();
  Frame f;
  std::vector<Eigen::Isometry3d, Eigen::aligned_allocator<Eigen::Isometry3d>> truth;
  while (source.next(f)) {
    pipeline.process(f);
    truth.push_back(f.raw.get<Eigen::Isometry3d>("ground_truth"));
    f = Frame();
  }
  const RunResult r = pipeline.result();
  ASSERT_EQ(r.reference.size(), truth.size());
  for (size_t k = 0; k < truth.size(); ++k)
    EXPECT_TRUE(r.reference[k].pose.isApprox(truth[k], 0.0));
}

TEST(Simulator3DSource, StereoFramesAreKittiLike) {
  Simulator3DSource source;
  source.world = std::string("street");
  source.camera = std::string("stereo");
  const Frame f = firstFrame(source);
  EXPECT_GT(source.sizeHint(), 400);  // about 500 m of block loop at 0.8 m per frame
  const auto& left = f.raw.get<Image>("left");
  const auto& right = f.raw.get<Image>("right");
  EXPECT_EQ(left.width, 1241);
  EXPECT_EQ(left.height, 376);
  EXPECT_EQ(left.channels, 1);
  EXPECT_EQ(right.width, 1241);
  EXPECT_NE(left.data, right.data);
  EXPECT_NEAR(f.raw.get<CameraInfo>("camera").baseline, 0.54, 1e-12);
}

TEST(Simulator3DSource, BadParametersAreRejected) {
  Simulator3DSource source;
  source.kitti_times = std::string("times.txt");
  EXPECT_THROW(source.configure(), ParamError);
  Simulator3DSource missing;
  missing.trajectory = std::string("/nonexistent/trajectory.txt");
  EXPECT_THROW(missing.configure(), InputError);
}

TEST(Simulator3DSource, APannedCameraTurnsAboutTheVerticalOnTheSamePath) {
  Simulator3DSource still, panned;
  still.duration = 2.0;
  panned.duration = 2.0;
  panned.pan = 60.0;
  panned.pan_period = 2.0;
  still.configure();
  panned.configure();
  const Trajectory& a = still.simulator().trajectory();
  const Trajectory& b = panned.simulator().trajectory();
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_TRUE(a[k].pose.translation().isApprox(b[k].pose.translation(), 1e-12)) << k;
    // Turned about the world's vertical (z up) by 60 deg * sin(2 pi t / 2 s).
    const double angle = M_PI / 3.0 * std::sin(M_PI * a[k].t);
    const Eigen::Matrix3d turn = b[k].pose.linear() * a[k].pose.linear().transpose();
    EXPECT_TRUE(
        turn.isApprox(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix(), 1e-9))
        << k;
  }
  // The vehicle's wheel odometry cannot follow a camera turning on it.
  Simulator3DSource on_car;
  on_car.world = std::string("street");
  on_car.camera = std::string("stereo");
  on_car.odometry = std::string("odom");
  on_car.pan = 30.0;
  EXPECT_THROW(on_car.configure(), ParamError);
}

// The real trajectory's relative motion is kept exactly (up to the anchoring transform).
void expectSameMotion(const Trajectory& file, const Trajectory& sim, size_t stride) {
  ASSERT_EQ(file.size(), sim.size());
  for (size_t k = stride; k < file.size(); k += stride) {
    const Eigen::Isometry3d a = file[0].pose.inverse() * file[k].pose;
    const Eigen::Isometry3d b = sim[0].pose.inverse() * sim[k].pose;
    ASSERT_TRUE(a.isApprox(b, 1e-9)) << k;
    ASSERT_EQ(file[k].t, sim[k].t);
  }
}

TEST(Simulator3DSource, RealKitti00TrajectoryInTheStreet) {
  const fs::path dir = fs::path(testing::dataDir()) / "stereo" / "kitti00-trajectories-evo";
  if (!fs::exists(dir / "KITTI_00_gt.txt")) GTEST_SKIP() << "no KITTI 00 poses under " << dir;
  Simulator3DSource source;
  source.world = std::string("street");
  source.camera = std::string("stereo");
  source.trajectory = (dir / "KITTI_00_gt.txt").string();
  source.kitti_times = (dir / "KITTI_00_gt_times.txt").string();
  source.configure();
  EXPECT_EQ(source.sizeHint(), 4541);
  const Trajectory file = readKittiTrajectory((dir / "KITTI_00_gt.txt").string(),
                                              (dir / "KITTI_00_gt_times.txt").string());
  expectSameMotion(file, source.simulator().trajectory(), 50);
  // The street follows the drive: under the camera there is road (1.65 m) or sidewalk
  // (1.53 m). Where the drive passes again (the loops of KITTI 00), the ground truth's heights
  // of the two passes differ by up to about 1.2 m and the higher ribbon shows, so some samples
  // see the road nearer; it is never above the camera.
  int on_road = 0, samples = 0;
  for (size_t k = 0; k < 4541; k += 50) {
    sim3d::RayHit down;
    const Eigen::Vector3d c = source.simulator().trajectory()[k].pose.translation();
    ASSERT_TRUE(source.simulator().world().castRay(c, -Eigen::Vector3d::UnitZ(), 5.0, &down)) << k;
    EXPECT_GT(down.distance, 0.3) << k;
    EXPECT_LT(down.distance, 1.7) << k;
    on_road += std::abs(down.distance - 1.65) < 0.05 || std::abs(down.distance - 1.53) < 0.05;
    ++samples;
  }
  EXPECT_GT(on_road, 0.75 * samples) << on_road << " of " << samples;
  // Buildings line the drive: above the horizon, many pixels hit something within 60 m.
  for (size_t k = 0; k < 4541; k += 1000) {
    sim3d::RenderBuffers buf;
    sim3d::render(source.simulator().world(), source.simulator().camera(),
                  source.simulator().trajectory()[k].pose, &buf, nullptr);
    size_t near = 0;
    for (int y = 0; y < 150; ++y)
      for (int x = 0; x < buf.width; ++x) {
        const double z = buf.depth[y * buf.width + x];
        near += z > 0.0 && z < 60.0;
      }
    EXPECT_GT(near, 150u * 1241u / 5) << k;
  }
}

TEST(Simulator3DSource, RealTumFr1XyzTrajectoryInTheLivingRoom) {
  const fs::path file = fs::path(testing::dataDir()) / "rgbd" / "tum-fr1_xyz-trajectories-evo" /
                        "freiburg1_xyz-groundtruth.txt";
  if (!fs::exists(file)) GTEST_SKIP() << "no TUM fr1_xyz ground truth at " << file;
  Simulator3DSource source;
  source.trajectory = file.string();
  source.configure();
  const Trajectory gt = readTumTrajectory(file.string());
  expectSameMotion(gt, source.simulator().trajectory(), 100);
  EXPECT_TRUE(source.simulator().trajectory()[0].pose.isApprox(sim3d::livingRoomStart(), 1e-9));
  // Resampled to 30 Hz.
  Simulator3DSource at30;
  at30.trajectory = file.string();
  at30.rate = 30.0;
  at30.configure();
  const double span = gt.endTime() - gt.startTime();
  EXPECT_NEAR(static_cast<double>(at30.sizeHint()), std::floor(span * 30.0) + 1, 1.0);
  Frame f;
  ASSERT_TRUE(at30.next(f));
  size_t valid = 0;
  for (float z : f.raw.get<DepthImage>("depth").data) valid += z > 0;
  EXPECT_GT(valid, 640u * 480u / 2);
}

TEST(SimulatorMixed, PlanarScanMatchesTheRoomGeometry) {
  sim3d::World room;
  sim3d::Material m;
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                        Z = Eigen::Vector3d::UnitZ();
  room.addQuad({0, 0, 0}, X, Z, 8, 3, m, "south");
  room.addQuad({0, 6, 0}, X, Z, 8, 3, m, "north");
  room.addQuad({0, 0, 0}, Y, Z, 6, 3, m, "west");
  room.addQuad({8, 0, 0}, Y, Z, 6, 3, m, "east");
  sim2d::LaserConfig laser;
  laser.beams = 361;
  laser.fov = 2 * M_PI * 360.0 / 361.0;
  laser.mount = Eigen::Vector3d(0.2, 0.0, 0.0);
  laser.max_range = 30.0;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(2.0, 1.5, 0.0);
  LaserScan scan;
  sim3d::castPlanarScan(room, base, 0.3, laser, nullptr, &scan);
  ASSERT_EQ(scan.ranges.size(), 361u);
  // Sensor at (2.2, 1.5): the analytic distance to the rectangle's walls along each beam.
  for (size_t i = 0; i < scan.ranges.size(); ++i) {
    const double a = scan.angle(i);
    const double c = std::cos(a), s = std::sin(a);
    double expected = 1e9;
    if (c > 1e-12) expected = std::min(expected, (8.0 - 2.2) / c);
    if (c < -1e-12) expected = std::min(expected, -2.2 / c);
    if (s > 1e-12) expected = std::min(expected, (6.0 - 1.5) / s);
    if (s < -1e-12) expected = std::min(expected, -1.5 / s);
    EXPECT_NEAR(scan.ranges[i], expected, 1e-9) << i;
  }
}

TEST(SimulatorMixed, SourceGivesLaserRgbdOdometryAndGroundTruth) {
  SimulatorMixedSource source;
  source.path_length = 3.0;
  Frame f = firstFrame(source);
  ASSERT_GT(source.sizeHint(), 10);
  const auto& scan = f.raw.get<LaserScan>("front_laser");
  size_t returns = 0;
  for (size_t i = 0; i < scan.ranges.size(); ++i) returns += scan.isReturn(i);
  EXPECT_GT(returns, 1000u);
  EXPECT_EQ(f.raw.get<Image>("rgb").channels, 3);
  EXPECT_EQ(f.raw.get<DepthImage>("depth").width, 640);
  EXPECT_NEAR(f.raw.get<CameraInfo>("camera").mount.translation().z(), 1.0, 1e-12);
  EXPECT_TRUE(f.raw.holds<Odometry2D>("odom"));
  EXPECT_TRUE(f.raw.holds<Eigen::Isometry3d>("ground_truth"));
  int frames = 1;
  while (source.next(f)) ++frames;
  EXPECT_EQ(frames, source.sizeHint());
}

}  // namespace
}  // namespace plugslam::sim
