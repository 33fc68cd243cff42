// OccupancyMapWriter: a square room gives occupied walls, free inside, unknown outside; the
// files exist, the YAML parses and the PNG is well formed.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "occupancy_grid.h"
#include "occupancy_map_writer.h"
#include "plugslam/pose_space.h"
#include "scan_preprocessor.h"
#include "synthetic.h"
#include "temp_dir.h"

namespace plugslam::laser2d {
namespace {

// This test process's own fresh temporary folder.
const plugslam::testing::TempDir& scratch() {
  static const plugslam::testing::TempDir tmp("laser2d_occupancy");
  return tmp;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

TEST(OccupancyGrid, RayMarksFreeCellsAndTheHit) {
  OccupancyGrid grid(0.1, Eigen::Vector2d(0, 0), Eigen::Vector2d(5, 5));
  grid.traceRay(Eigen::Vector2d(0.05, 0.05), Eigen::Vector2d(3.05, 0.05));
  EXPECT_GT(grid.probability(30, 0), 0.6);
  for (int x = 0; x < 30; ++x) EXPECT_LT(grid.probability(x, 0), 0.5) << x;
  EXPECT_TRUE(grid.unknown(31, 0));
  EXPECT_TRUE(grid.unknown(10, 3));
}

TEST(OccupancyMapWriter, SquareRoomMap) {
  const auto world = test::box(0, 0, 4, 4);
  const auto dir = scratch().path() / "laser2d_occupancy_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);

  ScanPreprocessor pre;
  pre.configure();
  OccupancyMapWriter writer;
  writer.resolution = 0.05;
  writer.begin(dir.string());
  RunResult result;
  // The robot's frames: scans taken in the robot frame; the trajectory places them.
  std::vector<SE2> poses;
  for (double x : {1.0, 2.0, 3.0})
    for (double y : {1.0, 2.0, 3.0}) poses.push_back(se2(x, y, 0.3 * x - 0.7 * y));
  test::ScanSpec spec;
  spec.mount = se2(0.2, 0.0, 0.0);
  for (size_t i = 0; i < poses.size(); ++i) {
    Frame frame;
    frame.seq = i;
    frame.stamp = 10.0 + i;
    frame.raw.set("front_laser", test::castScan(world, poses[i], spec));
    pre.process(frame);
    writer.consume(frame);
    result.trajectory.push_back(frame.stamp, Space2D::to3D(poses[i]));
  }
  writer.end(result);
  EXPECT_EQ(writer.placedScans(), poses.size());
  ASSERT_EQ(writer.written().size(), 3u);
  for (const char* ext : {".pgm", ".yaml", ".png"})
    EXPECT_TRUE(std::filesystem::exists(dir / (std::string("map") + ext))) << ext;

  const YAML::Node yaml = YAML::LoadFile((dir / "map.yaml").string());
  EXPECT_EQ(yaml["image"].as<std::string>(), "map.pgm");
  const double res = yaml["resolution"].as<double>();
  EXPECT_DOUBLE_EQ(res, 0.05);
  const auto origin = yaml["origin"].as<std::vector<double>>();
  ASSERT_EQ(origin.size(), 3u);
  EXPECT_EQ(yaml["negate"].as<int>(), 0);
  EXPECT_DOUBLE_EQ(yaml["occupied_thresh"].as<double>(), 0.65);
  EXPECT_DOUBLE_EQ(yaml["free_thresh"].as<double>(), 0.196);

  // Read the PGM back and look at cells through the map_server convention.
  const std::string pgm = readAll((dir / "map.pgm").string());
  std::istringstream in(pgm);
  std::string magic;
  int w, h, maxval;
  in >> magic >> w >> h >> maxval;
  in.get();
  ASSERT_EQ(magic, "P5");
  ASSERT_EQ(maxval, 255);
  const size_t header = static_cast<size_t>(in.tellg());
  ASSERT_EQ(pgm.size(), header + static_cast<size_t>(w) * h);
  auto pixel = [&](double x, double y) {
    const int cx = static_cast<int>(std::floor((x - origin[0]) / res));
    const int cy = static_cast<int>(std::floor((y - origin[1]) / res));
    EXPECT_TRUE(cx >= 0 && cy >= 0 && cx < w && cy < h);
    return static_cast<uint8_t>(pgm[header + static_cast<size_t>(h - 1 - cy) * w + cx]);
  };
  // Walls occupied (sampled away from the exact cell boundary), inside free.
  int occupied = 0, samples = 0;
  for (double t = 0.3; t < 3.8; t += 0.25) {
    // A wall on a cell boundary lands on either side of it: look at both.
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(t, 0.0), Eigen::Vector2d(4.0, t),
                                     Eigen::Vector2d(t, 4.0), Eigen::Vector2d(0.0, t)}) {
      const Eigen::Vector2d d = p.x() == t ? Eigen::Vector2d(0, 0.02) : Eigen::Vector2d(0.02, 0);
      occupied +=
          pixel(p.x() + d.x(), p.y() + d.y()) == 0 || pixel(p.x() - d.x(), p.y() - d.y()) == 0;
      ++samples;
    }
  }
  EXPECT_GT(occupied, samples * 9 / 10) << occupied << " of " << samples;
  for (double x = 0.5; x < 3.6; x += 0.5)
    for (double y = 0.5; y < 3.6; y += 0.5) EXPECT_EQ(pixel(x, y), 254) << x << ", " << y;

  const std::string png = readAll((dir / "map.png").string());
  ASSERT_GT(png.size(), 8u + 25u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
  std::filesystem::remove_all(dir);
}

TEST(OccupancyMapWriter, NoPlaceableScanWritesNothing) {
  const auto dir = scratch().path() / "laser2d_occupancy_empty";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  OccupancyMapWriter writer;
  writer.begin(dir.string());
  writer.end(RunResult{});
  EXPECT_TRUE(writer.written().empty());
  EXPECT_FALSE(std::filesystem::exists(dir / "map.pgm"));
  std::filesystem::remove_all(dir);
}

TEST(OccupancyMapWriter, SaveActionWritesTheMapMidRun) {
  const auto world = test::box(0, 0, 4, 4);
  const auto dir = scratch().path() / "laser2d_occupancy_save_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  ScanPreprocessor pre;
  pre.configure();
  OccupancyMapWriter writer;
  writer.begin(dir.string());
  EXPECT_EQ(writer.invoke("save"), "no map written (no scan placed yet)");
  test::ScanSpec spec;
  for (int i = 0; i < 3; ++i) {
    Frame frame;
    frame.seq = i;
    frame.stamp = 1.0 + i;
    const SE2 pose = se2(1.0 + i, 2.0, 0.1 * i);
    frame.raw.set("front_laser", test::castScan(world, pose, spec));
    pre.process(frame);
    // What the tracker leaves on a frame: its pose estimate at the time.
    frame.estimate.valid = true;
    frame.estimate.local_map = 0;
    frame.estimate.in_map = Space2D::to3D(pose);
    frame.estimate.world = Space2D::to3D(pose);
    writer.consume(frame);
  }
  const std::string msg = writer.invoke("save");
  EXPECT_NE(msg.find("wrote"), std::string::npos) << msg;
  EXPECT_EQ(writer.placedScans(), 3u);
  EXPECT_TRUE(std::filesystem::exists(dir / "map.pgm"));
  std::filesystem::remove_all(dir);
}

// Memory grows with the mapped space, not with time: passing the same places again (a
// localization run, a looping replay) or standing still keeps no further cloud.
TEST(OccupancyMapWriter, KeepsCloudsOnlyForNewPosesInTheirLocalMap) {
  const auto world = test::box(0, 0, 4, 4);
  ScanPreprocessor pre;
  pre.configure();
  OccupancyMapWriter writer;
  writer.begin(scratch().path().string());
  test::ScanSpec spec;
  uint64_t seq = 0;
  auto feed = [&](int64_t map, const SE2& in_map) {
    Frame frame;
    frame.seq = seq;
    frame.stamp = 1.0 + 0.1 * static_cast<double>(seq++);
    frame.raw.set("front_laser", test::castScan(world, in_map, spec));
    pre.process(frame);
    frame.estimate.valid = true;
    frame.estimate.local_map = map;
    frame.estimate.in_map = Space2D::to3D(in_map);
    frame.estimate.world = Space2D::to3D(in_map);
    writer.consume(frame);
  };
  const std::vector<SE2> path = {se2(1, 1, 0), se2(1.5, 1, 0), se2(2, 1, 0.2), se2(2, 1.5, 0.6)};
  for (int pass = 0; pass < 10; ++pass)
    for (const auto& p : path) feed(0, p);
  EXPECT_EQ(writer.seenFrames(), 40u);
  EXPECT_EQ(writer.keptScans(), 4u);
  for (int i = 0; i < 50; ++i) feed(0, se2(1.01, 1.0, 0.01));  // standing still, a little noise
  EXPECT_EQ(writer.keptScans(), 4u);
  feed(0, se2(1, 1, 0.5));  // turned on the spot: new
  feed(1, se2(1, 1, 0));    // the same pose in another local map: new
  EXPECT_EQ(writer.keptScans(), 6u);
  // The cap per local map.
  writer.max_scans_per_map = 7;
  for (int i = 0; i < 20; ++i) feed(0, se2(0.5 + 0.1 * i, 2.0, 0.0));
  EXPECT_EQ(writer.keptScans(), 8u);  // map 0 holds 7, map 1 holds 1
}

TEST(TiledOccupancyGrid, MatchesTheDenseGridOnItsLatticeAndGrowsWithAreaOnly) {
  const double res = 0.1;
  OccupancyGrid dense(res, Eigen::Vector2d(-5, -5), Eigen::Vector2d(5, 5));
  TiledOccupancyGrid tiled(res);
  EXPECT_TRUE(tiled.empty());
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> rays = {
      {{0.05, 0.05}, {3.05, 0.05}},
      {{-0.33, 0.21}, {-4.13, -3.67}},
      {{1.01, -2.23}, {-1.33, 4.43}}};
  for (const auto& [a, b] : rays) {
    dense.traceRay(a, b);
    EXPECT_TRUE(tiled.traceRay(a, b));
  }
  // The dense grid's origin is a multiple of the cell: its cells are the tiled grid's, shifted
  // (the ends are away from cell borders, where the two roundings may differ).
  const Eigen::Vector2i offset((dense.origin() / res).array().round().cast<int>());
  size_t cells = 0;
  tiled.forEachCell([&](int x, int y, double v) {
    ++cells;
    EXPECT_NEAR(dense.logOdds(x - offset.x(), y - offset.y()), v, 1e-6) << x << ", " << y;
  });
  size_t observed = 0;
  for (int y = 0; y < dense.height(); ++y)
    for (int x = 0; x < dense.width(); ++x) observed += !dense.unknown(x, y);
  EXPECT_EQ(cells, observed);
  EXPECT_EQ(tiled.minCell(), Eigen::Vector2i(-42, -37));
  EXPECT_EQ(tiled.maxCell(), Eigen::Vector2i(30, 44));
  // Tracing the same rays again changes the evidence, not the memory.
  const size_t tiles = tiled.tiles();
  EXPECT_GT(tiles, 1u);
  for (int i = 0; i < 20; ++i)
    for (const auto& [a, b] : rays) tiled.traceRay(a, b);
  EXPECT_EQ(tiled.tiles(), tiles);
  // Rays it cannot place are refused, not traced.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(tiled.traceRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(nan, 1)));
  EXPECT_FALSE(tiled.traceRay(Eigen::Vector2d(0, 0), Eigen::Vector2d(1e9, 1)));
  EXPECT_EQ(tiled.tiles(), tiles);
  tiled.clear();
  EXPECT_TRUE(tiled.empty());
}

// The occupancy map as map_server reads it: a cell's pixel by world position.
struct MapImage {
  explicit MapImage(const std::filesystem::path& yaml_path) {
    const YAML::Node yaml = YAML::LoadFile(yaml_path.string());
    res = yaml["resolution"].as<double>();
    origin = yaml["origin"].as<std::vector<double>>();
    const std::string pgm =
        readAll((yaml_path.parent_path() / yaml["image"].as<std::string>()).string());
    std::istringstream in(pgm);
    std::string magic;
    int maxval = 0;
    in >> magic >> w >> h >> maxval;
    in.get();
    pixels = pgm.substr(static_cast<size_t>(in.tellg()));
  }
  // 205 (unknown) outside the image.
  int at(double x, double y) const {
    const int cx = static_cast<int>(std::floor((x - origin[0]) / res));
    const int cy = static_cast<int>(std::floor((y - origin[1]) / res));
    if (cx < 0 || cy < 0 || cx >= w || cy >= h) return 205;
    return static_cast<uint8_t>(pixels[static_cast<size_t>(h - 1 - cy) * w + cx]);
  }
  double res = 0;
  std::vector<double> origin;
  int w = 0, h = 0;
  std::string pixels;
};

// Localization in a saved session: the frames' maps are frozen, so their world poses are final.
// The writer draws them at once and keeps nothing of them: passing the same places again (the
// soak's endless replays) leaves its memory as it was, and the map still shows the place, as the
// same frames mapped (kept, drawn at the end) do.
TEST(OccupancyMapWriter, FramesInFrozenMapsAreTracedAtOnceAndKeepNothing) {
  const auto world = test::box(0, 0, 4, 4);
  const auto dir = scratch().path() / "laser2d_occupancy_frozen";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "mapped");
  std::filesystem::create_directories(dir / "localized");
  ScanPreprocessor pre;
  pre.configure();
  OccupancyMapWriter mapped, localized;
  localized.file = "map";
  mapped.begin((dir / "mapped").string());
  localized.begin((dir / "localized").string());
  test::ScanSpec spec;
  spec.mount = se2(0.2, 0.0, 0.0);
  std::vector<SE2> poses;
  for (double x : {1.0, 2.0, 3.0})
    for (double y : {1.0, 2.0, 3.0}) poses.push_back(se2(x, y, 0.3 * x - 0.7 * y));
  RunResult mapped_result;
  uint64_t seq = 0;
  auto frameAt = [&](const SE2& pose, bool frozen) {
    Frame frame;
    frame.seq = seq;
    frame.stamp = 10.0 + static_cast<double>(seq++);
    frame.raw.set("front_laser", test::castScan(world, pose, spec));
    pre.process(frame);
    frame.estimate.valid = true;
    frame.estimate.local_map = 3;  // a saved map whose origin is the world's
    frame.estimate.in_map = Space2D::to3D(pose);
    frame.estimate.world = Space2D::to3D(pose);
    frame.estimate.frozen = frozen;
    return frame;
  };
  for (const auto& p : poses) {
    mapped.consume(frameAt(p, false));
    mapped_result.trajectory.push_back(10.0 + static_cast<double>(seq - 1), Space2D::to3D(p));
    localized.consume(frameAt(p, true));
  }
  EXPECT_EQ(localized.keptScans(), 0u);
  EXPECT_EQ(localized.tracedFrames(), poses.size());
  const size_t tiles = localized.tracedTiles();
  EXPECT_GT(tiles, 0u);
  // The same frames again, and again a little off (localization never lands twice on the same
  // pose): nothing kept, no tile added.
  for (int pass = 0; pass < 5; ++pass)
    for (const auto& p : poses)
      localized.consume(frameAt(p * se2(0.01 * pass, -0.01, 0.005), true));
  EXPECT_EQ(localized.keptScans(), 0u);
  EXPECT_EQ(localized.tracedFrames(), 6 * poses.size());
  EXPECT_EQ(localized.tracedTiles(), tiles);
  // Standing still: seen, drawn once.
  for (int i = 0; i < 20; ++i) localized.consume(frameAt(se2(2.5, 2.5, 0.01 * (i % 2)), true));
  EXPECT_EQ(localized.tracedFrames(), 6 * poses.size() + 1);
  EXPECT_EQ(localized.seenFrames(), 6 * poses.size() + 20);
  EXPECT_EQ(localized.keptScans(), 0u);
  // A lost frame (its pose predicted, not measured) is not drawn: a lost robot drifting through
  // the world would otherwise paint new area for as long as it runs.
  for (int i = 0; i < 10; ++i) {
    Frame lost = frameAt(se2(20.0 + i, 20.0, 0.0), true);
    lost.estimate.lost = true;
    localized.consume(lost);
  }
  EXPECT_EQ(localized.tracedFrames(), 6 * poses.size() + 1);
  EXPECT_EQ(localized.tracedTiles(), tiles);

  mapped.end(mapped_result);
  localized.end(RunResult{});  // needs no trajectory: the frames were placed when they came
  ASSERT_EQ(localized.written().size(), 3u);
  const MapImage a(dir / "mapped" / "map.yaml"), b(dir / "localized" / "map.yaml");
  // Inside free, outside unknown, the walls occupied, as in the mapped map.
  for (double x = 0.5; x < 3.6; x += 0.5)
    for (double y = 0.5; y < 3.6; y += 0.5) EXPECT_EQ(b.at(x, y), 254) << x << ", " << y;
  EXPECT_EQ(b.at(-0.5, 2.0), 205);
  int walls = 0, agree = 0, cells = 0;
  for (double t = 0.3; t < 3.8; t += 0.25) {
    // A wall on a cell border lands on either side of it.
    walls += b.at(t, 0.02) == 0 || b.at(t, -0.02) == 0;
    walls += b.at(4.02, t) == 0 || b.at(3.98, t) == 0;
  }
  EXPECT_GE(walls, 26);
  for (double x = -0.3; x < 4.3; x += 0.05)
    for (double y = -0.3; y < 4.3; y += 0.05) {
      agree += a.at(x + 0.01, y + 0.01) == b.at(x + 0.01, y + 0.01);
      ++cells;
    }
  EXPECT_GT(agree, cells * 97 / 100) << agree << " of " << cells;
  // The shell's `save` mid-run draws the traced frames too.
  EXPECT_NE(localized.invoke("save").find("wrote"), std::string::npos);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace plugslam::laser2d
