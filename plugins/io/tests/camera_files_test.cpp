// The text files of the camera layouts: KITTI calibration and times, EuRoC lists, sensor.yaml
// and ground truth, TUM lists and their association, K matrices and pose lists.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "plugslam/errors.h"
#include "readers/euroc_files.h"
#include "readers/kitti_files.h"
#include "readers/text_table.h"
#include "readers/tum_files.h"

namespace plugslam::io {
namespace {

std::string errorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const ParseError& e) {
    return e.what();
  }
  return "no ParseError";
}

const char* kKittiCalib =
    "P0: 7.188560000000e+02 0 6.071928000000e+02 0 0 7.188560000000e+02 1.852157000000e+02 0 0 "
    "0 1 0\n"
    "P1: 7.188560000000e+02 0 6.071928000000e+02 -3.861448000256e+02 0 7.188560000000e+02 "
    "1.852157000000e+02 0 0 0 1 0\n"
    "P2: 7.188560000000e+02 0 6.071928000000e+02 4.538225000000e+01 0 7.188560000000e+02 "
    "1.852157000000e+02 -1.130887000000e-01 0 0 1 3.779761000000e-03\n"
    "P3: 7.188560000000e+02 0 6.071928000000e+02 -3.372877000000e+02 0 7.188560000000e+02 "
    "1.852157000000e+02 2.369057000000e+00 0 0 1 4.915215000000e-03\n";

TEST(KittiFiles, GreyPairFromP0AndP1) {
  const KittiCalibration calib = parseKittiCalibration(kKittiCalib, "calib.txt");
  const CameraInfo c = rectifiedPair(calib, "P0", "P1", 1241, 376);
  EXPECT_DOUBLE_EQ(c.fx, 718.856);
  EXPECT_DOUBLE_EQ(c.cy, 185.2157);
  EXPECT_NEAR(c.baseline, 386.1448000256 / 718.856, 1e-12);
  EXPECT_EQ(c.width, 1241);
  EXPECT_TRUE(c.mount.isApprox(Eigen::Isometry3d::Identity()));
  ASSERT_TRUE(c.second.has_value());
  EXPECT_DOUBLE_EQ(c.second->fx, 718.856);
  EXPECT_NEAR(c.second_pose.translation().x(), c.baseline, 1e-15);
  EXPECT_EQ(c.distortion.model, Distortion::Model::kNone);
}

TEST(KittiFiles, ColourPairSitsBesideCameraZero) {
  // KITTI odometry 00's P2/P3: camera 2 sits 6 cm to the left of camera 0.
  const CameraInfo c =
      rectifiedPair(parseKittiCalibration(kKittiCalib, "calib.txt"), "P2", "P3", 1241, 376);
  // P = K [I | t]: t_x = (P[0,3] - cx P[2,3]) / fx, and the camera centre is at -t.
  const double t2 = (45.38225 - 607.1928 * 3.779761e-03) / 718.856;
  const double t3 = (-337.2877 - 607.1928 * 4.915215e-03) / 718.856;
  EXPECT_NEAR(c.mount.translation().x(), -t2, 1e-9);
  EXPECT_NEAR(c.mount.translation().z(), -3.779761e-03, 1e-12);
  EXPECT_NEAR(c.baseline, t2 - t3, 1e-9);
}

TEST(KittiFiles, MissingKeyAndWrongCountAreNamed) {
  const KittiCalibration only_p0 =
      parseKittiCalibration(std::string(kKittiCalib).substr(0, std::string(kKittiCalib).find("P1:")),
                            "seq/calib.txt");
  const std::string e = errorOf([&] { rectifiedPair(only_p0, "P0", "P1", 10, 10); });
  EXPECT_NE(e.find("seq/calib.txt"), std::string::npos) << e;
  EXPECT_NE(e.find("missing key 'P1' (keys present: P0)"), std::string::npos) << e;
  const KittiCalibration short_p1 = parseKittiCalibration("P0: 1 0 0 0 0 1 0 0 0 0 1 0\nP1: 1 2\n", "c.txt");
  EXPECT_NE(errorOf([&] { short_p1.projection("P1"); }).find("c.txt:2: P1: expected 12 numbers, got 2"),
            std::string::npos);
  const KittiCalibration bad = parseKittiCalibration("P0: 1 0 0 x 0 1 0 0 0 0 1 0\n", "c.txt");
  EXPECT_NE(errorOf([&] { bad.projection("P0"); }).find("'x' is not a finite number"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseKittiCalibration("P0 1 2 3\n", "c.txt"); }).find("expected 'KEY: values'"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseKittiCalibration("P0: 1\nP0: 2\n", "c.txt"); }).find("twice"),
            std::string::npos);
}

TEST(KittiFiles, PairsThatAreNotRectifiedAreRefused) {
  const auto calib = parseKittiCalibration(
      "P0: 700 0 600 0 0 700 180 0 0 0 1 0\n"
      "P1: 710 0 600 -380 0 700 180 0 0 0 1 0\n"
      "P2: 700 0 600 380 0 700 180 0 0 0 1 0\n",
      "c.txt");
  EXPECT_NE(errorOf([&] { rectifiedPair(calib, "P0", "P1", 10, 10); }).find("different intrinsics"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { rectifiedPair(calib, "P0", "P2", 10, 10); }).find("to the right"),
            std::string::npos);
}

TEST(KittiFiles, CalibCamToCamKeepsTextLines) {
  const KittiCalibration c = parseKittiCalibration(
      "calib_time: 09-Jan-2012 13:57:47\ncorner_dist: 9.950000e-02\nS_rect_00: 1.242e+03 3.75e+02\n",
      "calib_cam_to_cam.txt");
  EXPECT_TRUE(c.has("calib_time"));
  EXPECT_EQ(c.numbers("S_rect_00", 2), (std::vector<double>{1242, 375}));
}

TEST(KittiFiles, TimesAndRawTimestamps) {
  EXPECT_EQ(parseKittiTimes("0.000000e+00\n1.037359e-01\n", "times.txt"),
            (std::vector<double>{0.0, 0.1037359}));
  EXPECT_NE(errorOf([&] { parseKittiTimes("0.0\n0.1 0.2\n", "times.txt"); }).find("times.txt:2"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseKittiTimes("0.0\n\n0.2\n", "times.txt"); }).find("indexed by line"),
            std::string::npos);
  const auto t = parseKittiRawTimestamps(
      "2011-09-26 13:02:25.967790592\n2011-09-26 13:02:26.070920448\n", "timestamps.txt");
  ASSERT_EQ(t.size(), 2u);
  // 2011-09-26 00:00:00 UTC = 1316995200 s since the epoch.
  EXPECT_NEAR(t[0], 1316995200.0 + 13 * 3600 + 2 * 60 + 25.967790592, 1e-6);
  EXPECT_NEAR(t[1] - t[0], 0.103129856, 1e-6);
  for (const char* bad : {"2011-09-26 13:02\n", "2011-13-26 13:02:25.1\n", "2011-09-26T13:02:25\n",
                          "2011-09-26 13:02:25.\n", "2011-09-26 13:02:25.1234567890\n"})
    EXPECT_NE(errorOf([&] { parseKittiRawTimestamps(bad, "ts.txt"); }).find("expected 'YYYY-MM-DD"),
              std::string::npos)
        << bad;
}

const char* kSensorYaml =
    "%YAML:1.0\n"
    "sensor_type: camera\n"
    "T_BS:\n"
    "  cols: 4\n"
    "  rows: 4\n"
    "  data: [0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975,\n"
    "         0.999557249008, 0.0149672133247, 0.025715529948, -0.064676986768,\n"
    "        -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,\n"
    "         0.0, 0.0, 0.0, 1.0]\n"
    "rate_hz: 20\n"
    "resolution: [752, 480]\n"
    "camera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv\n"
    "distortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n";

TEST(EurocFiles, SensorYaml) {
  const EurocCamera c = parseEurocSensor(kSensorYaml, "cam0/sensor.yaml");
  EXPECT_EQ(c.intrinsics.width, 752);
  EXPECT_EQ(c.intrinsics.height, 480);
  EXPECT_DOUBLE_EQ(c.intrinsics.fx, 458.654);
  EXPECT_DOUBLE_EQ(c.intrinsics.cy, 248.375);
  EXPECT_EQ(c.intrinsics.distortion.model, Distortion::Model::kRadialTangential);
  EXPECT_EQ(c.intrinsics.distortion.coefficients.size(), 4u);
  EXPECT_NEAR(c.T_BS.translation().y(), -0.064676986768, 1e-12);
  EXPECT_NEAR(c.T_BS.linear()(0, 1), -0.999880929698, 1e-9);
}

TEST(EurocFiles, SensorYamlMissingOrBadKeysAreNamed) {
  const std::string yaml = kSensorYaml;
  auto without = [&](const std::string& key) {
    std::string s = yaml;
    const std::size_t at = s.find(key + ":");
    return s.substr(0, at) + s.substr(s.find('\n', at) + 1);
  };
  for (const char* key : {"intrinsics", "resolution", "distortion_model", "distortion_coefficients",
                          "camera_model"}) {
    const std::string e = errorOf([&] { parseEurocSensor(without(key), "cam1/sensor.yaml"); });
    EXPECT_NE(e.find("cam1/sensor.yaml"), std::string::npos) << e;
    EXPECT_NE(e.find(std::string("missing key '") + key + "'"), std::string::npos) << e;
  }
  std::string no_tbs = yaml.substr(0, yaml.find("T_BS:")) + yaml.substr(yaml.find("rate_hz"));
  EXPECT_NE(errorOf([&] { parseEurocSensor(no_tbs, "s.yaml"); }).find("missing key 'T_BS'"),
            std::string::npos);
  std::string fisheye = yaml;
  fisheye.replace(fisheye.find("pinhole"), 7, "omni");
  EXPECT_NE(errorOf([&] { parseEurocSensor(fisheye, "s.yaml"); }).find("'omni' is not supported"),
            std::string::npos);
  std::string three = yaml;
  three.replace(three.find(", 1.76187114e-05"), 16, "");
  EXPECT_NE(errorOf([&] { parseEurocSensor(three, "s.yaml"); }).find("3 values do not fit"),
            std::string::npos);
  std::string skew = yaml;
  skew.replace(skew.find("0.0148655429818"), 15, "0.5");
  EXPECT_NE(errorOf([&] { parseEurocSensor(skew, "s.yaml"); }).find("not a rigid transform"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseEurocSensor("a: [1, 2\n", "s.yaml"); }).find("invalid YAML"),
            std::string::npos);
}

// What the camera-files fuzzer found: 8.8e57 pixels, cast to int, was undefined behaviour.
TEST(EurocFiles, AResolutionOutsideWholePixelsIsNamedAtItsLine) {
  const std::string yaml = kSensorYaml;
  auto with = [&](const std::string& resolution) {
    std::string s = yaml;
    return s.replace(s.find("[752, 480]"), 10, resolution);
  };
  for (const auto& [res, what] :
       {std::pair{"[8.77777e57, 480]", "got width 8.77777e+57"},
        std::pair{"[752, -1e300]", "got height -1e+300"},
        std::pair{"[752.5, 480]", "got width 752.5"}, std::pair{"[0, 480]", "got width 0"},
        std::pair{"[752, 65537]", "got height 65537"}}) {
    try {
      parseEurocSensor(with(res), "cam0/sensor.yaml");
      ADD_FAILURE() << res << " read";
    } catch (const ParseError& e) {
      EXPECT_EQ(e.file(), "cam0/sensor.yaml");
      EXPECT_EQ(e.line(), 11) << res;
      EXPECT_EQ(
          e.message(),
          std::string("resolution: expected [width, height] in whole pixels from 1 to 65536, ") +
              what);
    }
  }
  EXPECT_EQ(parseEurocSensor(with("[65536, 1]"), "s.yaml").intrinsics.width, 65536);
}

// The SDK's YAML loading: an alias inside its own anchor is refused at its line, not walked.
TEST(EurocFiles, ASensorYamlWithAnAliasCycleIsAParseError) {
  try {
    parseEurocSensor(std::string(kSensorYaml) + "extra: &e\n  - [1, *e]\n", "cam0/sensor.yaml");
    FAIL() << "read";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), "cam0/sensor.yaml");
    EXPECT_EQ(e.line(), 17);
    EXPECT_NE(e.message().find("alias *e is inside its own anchor &e"), std::string::npos)
        << e.message();
  }
}

TEST(EurocFiles, ImageListAndGroundTruth) {
  const auto list = parseEurocImageList(
      "#timestamp [ns],filename\n1403715273262142976,1403715273262142976.png\n"
      "1403715273312143104, 1403715273312143104.png\n",
      "data.csv");
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[1].stamp_ns, 1403715273312143104LL);
  EXPECT_EQ(list[1].file, "1403715273312143104.png");
  EXPECT_NE(errorOf([&] { parseEurocImageList("5,a.png\n4,b.png\n", "data.csv"); }).find("does not follow"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseEurocImageList("5.5,a.png\n", "data.csv"); }).find("not an integer"),
            std::string::npos);
  const Trajectory gt = parseEurocGroundTruth(
      "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []\n"
      "1403715274312143104.0000000000,0.8687393558,2.2070275302,0.9257726725,0.4259596512,"
      "0.6262011737,-0.5441421096,0.361026079545\n",
      "gt.txt");
  ASSERT_EQ(gt.size(), 1u);
  EXPECT_NEAR(gt[0].t, 1403715274.312143104, 1e-6);
  EXPECT_NEAR(gt[0].pose.translation().y(), 2.2070275302, 1e-12);
  const Eigen::Quaterniond q(gt[0].pose.rotation());
  EXPECT_NEAR(q.w(), 0.4259596512, 1e-9);  // w first in EuRoC's files
  EXPECT_NE(errorOf([&] { parseEurocGroundTruth("1,0,0,0,2,0,0,0\n", "gt.txt"); }).find("norm"),
            std::string::npos);
}

TEST(TumFiles, ListsAndAssociation) {
  const auto rgb = parseTumList("# colour\n1.00 rgb/1.00.png\n1.033 rgb/1.033.png\n1.066 rgb/1.066.png\n",
                                "rgb.txt");
  const auto depth = parseTumList("1.01 d/a.png\n1.02 d/b.png\n1.10 d/c.png\n", "depth.txt");
  const auto pairs = associateByTime(rgb, depth, 0.02);
  // 1.00-1.01 (0.010) and 1.033-1.02 (0.013) pair; 1.066 has nothing within 0.02 (1.10: 0.034).
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].rgb, 0u);
  EXPECT_EQ(pairs[0].depth, 0u);
  EXPECT_EQ(pairs[1].rgb, 1u);
  EXPECT_EQ(pairs[1].depth, 1u);
  // Each depth image once: two colour images near one depth image, the closer wins.
  const auto one = parseTumList("2.0 d.png\n", "depth.txt");
  const auto two = parseTumList("1.995 a.png\n2.001 b.png\n", "rgb.txt");
  const auto p = associateByTime(two, one, 0.02);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].rgb, 1u);
  EXPECT_NE(errorOf([&] { parseTumList("1.0 a.png extra\n", "rgb.txt"); }).find("rgb.txt:1"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseTumList("2.0 a.png\n1.0 b.png\n", "rgb.txt"); }).find("backwards"),
            std::string::npos);
}

TEST(TumFiles, IntrinsicsMatrixAndPoseList) {
  const Eigen::Matrix3d K = parseIntrinsicsMatrix(
      "5.85e+02 0.0e+00 3.2e+02\n0.0e+00 5.85e+02 2.4e+02\n0.0e+00 0.0e+00 1.0e+00\n", "K.txt");
  EXPECT_EQ(K(0, 0), 585);
  EXPECT_EQ(K(1, 2), 240);
  EXPECT_NE(errorOf([&] { parseIntrinsicsMatrix("1 0 0\n0 1 0\n", "K.txt"); }).find("3 rows"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { parseIntrinsicsMatrix("1 2 0\n0 1 0\n0 0 1\n", "K.txt"); }).find("camera matrix"),
            std::string::npos);
  const auto poses = parsePoseList("1 2 3 0 0 0 1\n0 0 0 0 0 0.7071068 0.7071068\n", "pose.txt");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(poses[1].linear()(1, 0), 1.0, 1e-6);
  EXPECT_NE(errorOf([&] { parsePoseList("1 2 3 0 0 0\n", "pose.txt"); }).find("pose.txt:1: expected 7"),
            std::string::npos);
}

}  // namespace
}  // namespace plugslam::io
