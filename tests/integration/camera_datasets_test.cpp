// The camera dataset sources through the CLI on the real folders in $PLUGSLAM_DATA (each test
// skips, saying which folder, when it is absent), as a user runs them:
//   plugslam run CONFIG --set source.path=DIR -o OUT
// Each layout reads every frame with the dataset's own timestamps and ground truth (OUT/
// reference.tum against the dataset's index and pose files), a cut of a KITTI sequence reads
// the stamps and poses of its image numbers, and damaged copies of the real folders (symlinks to
// the real files, one file replaced: the data is never copied) stop with an error naming the
// file and the frame index, or the calibration file and key, or skip the frame with a warning
// (on_error: skip).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "images/png.h"
#include "plugslam/trajectory.h"
#include "run_command.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using namespace plugslam;

namespace {

struct TempDir : plugslam::testing::TempDir {
  TempDir() : plugslam::testing::TempDir("plugslam-camdata-") {}
};

std::string data(const std::string& folder) { return plugslam::testing::dataDir() + "/" + folder; }

#define SKIP_WITHOUT(folder)                                                                 \
  if (!fs::is_directory(data(folder)))                                                       \
  GTEST_SKIP() << "real data not found: " << data(folder)                                    \
               << " (set PLUGSLAM_DATA to the shared data folder)"

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

struct CliRun {
  int code = -1;
  std::string out;   // stdout + stderr
  fs::path out_dir;  // -o
};

// `plugslam run` of a config whose source is `source` (a YAML flow map), with --set arguments.
CliRun plugslam(const TempDir& tmp, const std::string& source, const std::vector<std::string>& sets) {
  const fs::path config = tmp.path() / "run.yaml";
  writeText(config, "plugins: [io]\nsource: " + source + "\n");
  CliRun r;
  r.out_dir = tmp.path() / "out";
  std::string cmd = "'" + plugslam::testing::buildDir() + "/bin/plugslam' run '" + config.string() +
                    "' -o '" + r.out_dir.string() + "'";
  for (const auto& s : sets) cmd += " --set '" + s + "'";
  const plugslam::testing::CommandResult ran = plugslam::testing::runCommand(cmd);
  r.code = ran.code;
  r.out = ran.out;
  return r;
}

// The folder `from` rebuilt under `to` from symlinks to its files, so one file can be replaced
// in the copy without touching (or copying) the data.
void mirror(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  for (const auto& e : fs::recursive_directory_iterator(from)) {
    const fs::path rel = fs::relative(e.path(), from);
    if (e.is_directory())
      fs::create_directories(to / rel);
    else
      fs::create_symlink(fs::absolute(e.path()), to / rel);
  }
}

// Replaces the (symlinked) file in a mirror with `bytes`.
void replace(const fs::path& file, const std::string& bytes) {
  fs::remove(file);
  writeText(file, bytes);
}

// The first `keep` bytes of a real file: a transfer cut short.
std::string truncated(const fs::path& real, size_t keep) { return slurp(real).substr(0, keep); }

// The text of a file without the lines that start with `prefix`.
std::string withoutLines(const fs::path& file, const std::string& prefix) {
  std::istringstream in(slurp(file));
  std::string line, out;
  while (std::getline(in, line))
    if (line.rfind(prefix, 0) != 0) out += line + "\n";
  return out;
}

// The first column of a whitespace- or comma-separated index file, `#` lines skipped, scaled.
std::vector<double> firstColumn(const fs::path& file, double scale = 1.0) {
  std::istringstream in(slurp(file));
  std::string line;
  std::vector<double> out;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    out.push_back(std::stod(line.substr(0, line.find_first_of(" ,\t"))) * scale);
  }
  return out;
}

// Runs `source` on a mirror `name` (in `tmp`) of the data folder `folder` that `damage` changed,
// and expects plugslam to refuse it as bad input (exit 2) naming each of `names`; returns the
// mirror, for a test that runs it again.
fs::path expectDamagedCopyRefused(const TempDir& tmp, const std::string& folder,
                                  const std::string& name, const std::string& source,
                                  const std::function<void(const fs::path& copy)>& damage,
                                  const std::vector<std::string>& names) {
  const fs::path copy = tmp.path() / name;
  mirror(data(folder), copy);
  damage(copy);
  const CliRun r = plugslam(tmp, source, {"source.path=" + copy.string()});
  EXPECT_EQ(r.code, 2) << r.out;
  for (const auto& n : names) EXPECT_TRUE(contains(r.out, n)) << n << "\n" << r.out;
  return copy;
}

// The stamps of OUT/reference.tum equal `stamps` (to the 1 ns the TUM writer prints).
void expectStamps(const Trajectory& reference, const std::vector<double>& stamps) {
  ASSERT_EQ(reference.size(), stamps.size());
  for (size_t i = 0; i < stamps.size(); ++i)
    EXPECT_NEAR(reference[i].t, stamps[i], 2e-6) << "frame " << i;
}

// Runs `source` on the data at `path` and reads the reference trajectory it wrote (empty, with
// a failure, when the run failed).
Trajectory runReference(const std::string& source, const std::string& path) {
  TempDir tmp;
  const CliRun r = plugslam(tmp, source, {"source.path=" + path});
  EXPECT_EQ(r.code, 0) << r.out;
  if (r.code != 0) return {};
  return readTumTrajectory((r.out_dir / "reference.tum").string());
}

// The poses of `reference` equal those of `truth` from its `first` on (to rounding).
void expectPoses(const Trajectory& reference, const Trajectory& truth, size_t first = 0) {
  ASSERT_LE(first + reference.size(), truth.size());
  for (size_t i = 0; i < reference.size(); ++i)
    EXPECT_LT((reference[i].pose.matrix() - truth[first + i].pose.matrix()).cwiseAbs().maxCoeff(),
              1e-8)
        << i;
}

// ---- KITTI odometry ------------------------------------------------------------------------

const char* kKitti = "{type: io.KittiSource, path: unset}";
const char* kKittiData = "stereo/kitti00-first5-srrg2";

TEST(CameraDatasets, KittiOdometryReadsEveryPairWithItsTimesAndPoses) {
  SKIP_WITHOUT(kKittiData);
  const Trajectory ref = runReference(kKitti, data(kKittiData));
  const std::vector<double> times = firstColumn(data(kKittiData) + "/times.txt");
  expectStamps(ref, std::vector<double>(times.begin(), times.begin() + 5));
  expectPoses(ref, readKittiTrajectory(data(kKittiData) + "/poses/00.txt"));
}

TEST(CameraDatasets, KittiCutIsIndexedByTheImageNumber) {
  SKIP_WITHOUT(kKittiData);
  TempDir tmp;
  // Images 2..4 of sequence 00 with the full times.txt and poses file.
  const fs::path cut = tmp.path() / "00";
  mirror(data(kKittiData), cut);
  for (const char* cam : {"image_0", "image_1"})
    for (const char* n : {"000000.png", "000001.png"}) fs::remove(cut / cam / n);
  const Trajectory ref = runReference(kKitti, cut.string());
  const std::vector<double> times = firstColumn(data(kKittiData) + "/times.txt");
  expectStamps(ref, {times[2], times[3], times[4]});
  expectPoses(ref, readKittiTrajectory(data(kKittiData) + "/poses/00.txt"), 2);
}

TEST(CameraDatasets, KittiTruncatedImageNamesFileAndFrameOrIsSkipped) {
  SKIP_WITHOUT(kKittiData);
  TempDir tmp;
  const fs::path copy =
      expectDamagedCopyRefused(tmp, kKittiData, "00", kKitti,
                               [&](const fs::path& copy) {
                                 replace(copy / "image_1/000003.png",
                                         truncated(data(kKittiData) + "/image_1/000003.png", 4000));
                               },
                               {"frame 3 of 5", "image_1/000003.png"});

  TempDir tmp2;
  const CliRun skip =
      plugslam(tmp2, kKitti, {"source.path=" + copy.string(), "source.on_error=skip"});
  ASSERT_EQ(skip.code, 0) << skip.out;
  EXPECT_TRUE(contains(skip.out, "image_1/000003.png")) << skip.out;
  EXPECT_TRUE(contains(skip.out, "skipped 1 of 5 frames")) << skip.out;
  const Trajectory ref = readTumTrajectory((skip.out_dir / "reference.tum").string());
  const std::vector<double> times = firstColumn(data(kKittiData) + "/times.txt");
  expectStamps(ref, {times[0], times[1], times[2], times[4]});
}

TEST(CameraDatasets, KittiMissingImageNamesFileAndFrame) {
  SKIP_WITHOUT(kKittiData);
  TempDir tmp;
  expectDamagedCopyRefused(tmp, kKittiData, "00", kKitti,
                           [&](const fs::path& copy) { fs::remove(copy / "image_1/000002.png"); },
                           {"frame 2 of 5", "image_1/000002.png"});
}

TEST(CameraDatasets, KittiCalibrationWithoutP1NamesFileAndKey) {
  SKIP_WITHOUT(kKittiData);
  TempDir tmp;
  expectDamagedCopyRefused(tmp, kKittiData, "00", kKitti,
                           [&](const fs::path& copy) {
                             replace(copy / "calib.txt",
                                     withoutLines(data(kKittiData) + "/calib.txt", "P1:"));
                           },
                           {"calib.txt", "P1"});
}

// ---- KITTI raw -----------------------------------------------------------------------------

const char* kKittiRawData = "stereo/kitti-raw-0001-stereo-soft";

TEST(CameraDatasets, KittiRawReadsEveryPair) {
  SKIP_WITHOUT(kKittiRawData);
  TempDir tmp;
  const CliRun r = plugslam(tmp, "{type: io.KittiRawSource, path: unset}",
                         {"source.path=" + data(kKittiRawData)});
  ASSERT_EQ(r.code, 0) << r.out;
  // KITTI raw has no camera poses: no reference, and every pair read.
  EXPECT_TRUE(contains(r.out, "60 frames")) << r.out;
  EXPECT_FALSE(fs::exists(r.out_dir / "reference.tum"));
  EXPECT_TRUE(contains(slurp(r.out_dir / "run.json"), "\"frames\": 60")) << slurp(r.out_dir / "run.json");
}

TEST(CameraDatasets, KittiRawCalibrationWithoutPRect01NamesFileAndKey) {
  SKIP_WITHOUT(kKittiRawData);
  TempDir tmp;
  const fs::path copy = tmp.path() / "2011_09_26_drive_0001_sync";
  mirror(data(kKittiRawData), copy);
  replace(copy / "calib_cam_to_cam.txt",
          withoutLines(data(kKittiRawData) + "/calib_cam_to_cam.txt", "P_rect_01:"));
  const CliRun r = plugslam(tmp, "{type: io.KittiRawSource, path: unset}",
                         {"source.path=" + copy.string()});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(contains(r.out, "calib_cam_to_cam.txt")) << r.out;
  EXPECT_TRUE(contains(r.out, "P_rect_01")) << r.out;
}

// ---- EuRoC ---------------------------------------------------------------------------------

const char* kEurocData = "stereo/euroc-v101-static-kimera";

TEST(CameraDatasets, EurocReadsEveryPairWithTheGroundTruthRows) {
  SKIP_WITHOUT(kEurocData);
  TempDir tmp;
  const CliRun r = plugslam(tmp, "{type: io.EurocSource, path: unset}",
                         {"source.path=" + data(kEurocData),
                          "source.ground_truth_file=" + data(kEurocData) + "/V101_GT_rows.txt"});
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "95 frames")) << r.out;
  // The ground-truth rows start at the 22nd image and fall on image times: the reference is
  // exactly those rows (body poses, EuRoC's nanosecond stamps).
  const Trajectory ref = readTumTrajectory((r.out_dir / "reference.tum").string());
  const std::vector<double> rows = firstColumn(data(kEurocData) + "/V101_GT_rows.txt", 1e-9);
  const std::vector<double> images = firstColumn(data(kEurocData) + "/mav0/cam0/data.csv", 1e-9);
  ASSERT_EQ(images.size(), 95u);
  std::vector<double> expected;
  for (double t : images)
    if (t >= rows.front() - 1e-6 && t <= rows.back() + 1e-6) expected.push_back(t);
  expectStamps(ref, expected);
  EXPECT_EQ(ref.size(), 74u);  // SOURCE.md: 74 ground-truth rows
}

TEST(CameraDatasets, EurocSensorYamlWithoutIntrinsicsNamesFileAndKey) {
  SKIP_WITHOUT(kEurocData);
  TempDir tmp;
  expectDamagedCopyRefused(
      tmp, kEurocData, "V101", "{type: io.EurocSource, path: unset}",
      [&](const fs::path& copy) {
        replace(copy / "mav0/cam1/sensor.yaml",
                withoutLines(data(kEurocData) + "/mav0/cam1/sensor.yaml", "intrinsics:"));
      },
      {"cam1/sensor.yaml", "intrinsics"});
}

TEST(CameraDatasets, EurocCorruptImageNamesFileAndFrame) {
  SKIP_WITHOUT(kEurocData);
  TempDir tmp;
  // Frame 40's left image (data.csv row 40; stamps have 19 digits: read the name as text):
  // its bytes past the header overwritten (a flipped disk block).
  std::istringstream csv(slurp(data(kEurocData) + "/mav0/cam0/data.csv"));
  std::string line, name;
  for (int row = -1; row < 40 && std::getline(csv, line);)
    if (!line.empty() && line[0] != '#') ++row;
  name = line.substr(line.find(',') + 1);
  while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
  const fs::path real = data(kEurocData) + "/mav0/cam0/data/" + name;
  ASSERT_TRUE(fs::exists(real)) << real;
  std::string bytes = slurp(real);
  for (size_t i = 100; i < bytes.size(); i += 7) bytes[i] = static_cast<char>(0x5a);
  expectDamagedCopyRefused(
      tmp, kEurocData, "V101", "{type: io.EurocSource, path: unset}",
      [&](const fs::path& copy) { replace(copy / "mav0/cam0/data" / name, bytes); },
      {"frame 40 of 95", "cam0/data/" + name});
}

// ---- TUM RGB-D layout: 7-Scenes indexed as TUM ---------------------------------------------

const char* kSevenScenes =
    "{type: io.TumRgbdSource, path: unset, intrinsics_file: camera-intrinsics.txt, "
    "depth_scale: 1000}";
const char* kSevenScenesData = "rgbd/7scenes-300frames-tsdf-fusion";

TEST(CameraDatasets, SevenScenesReadsEveryFrameWithItsStampsAndPoses) {
  SKIP_WITHOUT(kSevenScenesData);
  const Trajectory ref = runReference(kSevenScenes, data(kSevenScenesData));
  expectStamps(ref, firstColumn(data(kSevenScenesData) + "/rgb.txt"));
  const Trajectory gt = readTumTrajectory(data(kSevenScenesData) + "/groundtruth.txt");
  ASSERT_EQ(gt.size(), ref.size());
  expectPoses(ref, gt);
}

TEST(CameraDatasets, SevenScenesDepthOfTheWrongSizeNamesFileAndFrame) {
  SKIP_WITHOUT(kSevenScenesData);
  TempDir tmp;
  expectDamagedCopyRefused(tmp, kSevenScenesData, "7scenes", kSevenScenes,
                           [&](const fs::path& copy) {
                             // Frame 10's depth at half the resolution (a depth stream recorded at
                             // 320x240).
                             const fs::path depth = copy / "frame-000010.depth.png";
                             fs::remove(depth);
                             io::writePng16(depth.string(), 320, 240,
                                            std::vector<uint16_t>(320 * 240, 1500));
                           },
                           {"frame 10 of 300", "frame-000010.depth.png", "320x240"});
}

TEST(CameraDatasets, SevenScenesTruncatedJpegNamesFileAndFrame) {
  SKIP_WITHOUT(kSevenScenesData);
  TempDir tmp;
  expectDamagedCopyRefused(
      tmp, kSevenScenesData, "7scenes", kSevenScenes,
      [&](const fs::path& copy) {
        replace(copy / "frame-000123.color.jpg",
                truncated(data(kSevenScenesData) + "/frame-000123.color.jpg", 20000));
      },
      {"frame 123 of 300", "frame-000123.color.jpg"});
}

TEST(CameraDatasets, SevenScenesIntrinsicsFileCutShortIsNamed) {
  SKIP_WITHOUT(kSevenScenesData);
  TempDir tmp;
  expectDamagedCopyRefused(
      tmp, kSevenScenesData, "7scenes", kSevenScenes,
      [&](const fs::path& copy) {
        // Two rows of K: the third is missing.
        std::istringstream in(slurp(data(kSevenScenesData) + "/camera-intrinsics.txt"));
        std::string a, b;
        std::getline(in, a);
        std::getline(in, b);
        replace(copy / "camera-intrinsics.txt", a + "\n" + b + "\n");
      },
      {"camera-intrinsics.txt"});
}

// ---- RGB-D folders: ICL-NUIM in slambook's layout ------------------------------------------

const char* kIcl =
    "{type: io.RgbdFolderSource, path: unset, fx: 481.2, fy: -480.0, cx: 319.5, cy: 239.5, "
    "depth_scale: 5000}";
const char* kIclData = "rgbd/icl-5frames-slambook2";

TEST(CameraDatasets, IclFolderReadsEveryFrameWithItsPoses) {
  SKIP_WITHOUT(kIclData);
  const Trajectory ref = runReference(kIcl, data(kIclData));
  // Frames k = 0..4 at k / 30 s (the folder has no times; ICL-NUIM renders 30 Hz).
  expectStamps(ref, {0.0, 1 / 30.0, 2 / 30.0, 3 / 30.0, 4 / 30.0});
  // pose.txt's translations, with y mirrored (fy < 0: the source makes the frame right-handed).
  std::istringstream in(slurp(data(kIclData) + "/pose.txt"));
  for (size_t i = 0; i < ref.size(); ++i) {
    double tx, ty, tz;
    ASSERT_TRUE(in >> tx >> ty >> tz) << i;
    std::string rest;
    std::getline(in, rest);
    EXPECT_NEAR(ref[i].pose.translation().x(), tx, 1e-6) << i;
    EXPECT_NEAR(ref[i].pose.translation().y(), -ty, 1e-6) << i;
    EXPECT_NEAR(ref[i].pose.translation().z(), tz, 1e-6) << i;
  }
}

TEST(CameraDatasets, IclMissingDepthNamesFileAndFrame) {
  SKIP_WITHOUT(kIclData);
  TempDir tmp;
  const fs::path copy = expectDamagedCopyRefused(
      tmp, kIclData, "icl", kIcl, [&](const fs::path& copy) { fs::remove(copy / "depth/4.png"); },
      {"frame 3 of 5", "depth/4.png"});

  // Skipped: the other four frames keep their stamps and their lines of pose.txt.
  TempDir tmp2;
  const CliRun skip = plugslam(tmp2, kIcl, {"source.path=" + copy.string(), "source.on_error=skip"});
  ASSERT_EQ(skip.code, 0) << skip.out;
  const Trajectory ref = readTumTrajectory((skip.out_dir / "reference.tum").string());
  expectStamps(ref, {0.0, 1 / 30.0, 2 / 30.0, 4 / 30.0});
  // pose.txt line 5 (the last frame), y mirrored.
  EXPECT_NEAR(ref[3].pose.translation().x(), -0.0506775, 1e-6);
  EXPECT_NEAR(ref[3].pose.translation().y(), 0.0139318, 1e-6);
  EXPECT_NEAR(ref[3].pose.translation().z(), -0.990509, 1e-6);
}

}  // namespace
