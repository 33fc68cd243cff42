// Camera input from ROS 2 bags (issue 21): io.Ros2BagSource on MCAP files the test writes with
// the SDK's mcap::Writer and CDR laid out by hand (XCDR1, as cdr_messages_test.cpp): a stereo
// pair, RGB-D colour + depth (both depth encodings), a compressed colour image; the calibration
// and mounts from CameraInfo and /tf_static; every bad input (another encoding, a size that does
// not fit, a compressed image that does not decode) an error naming file, topic and offset, or a
// skip with a warning (on_error: skip). The same bags from independent implementations, and the
// trajectory of a simulated run, are node_ros2_bags_test's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <utility>

#include "images/image_file.h"
#include "images/png.h"
#include "plugslam/errors.h"
#include "plugslam/mcap/writer.h"
#include "readers/ros_images.h"
#include "sources/ros2_bag_source.h"
#include "cdr_writer.h"
#include "temp_dir.h"

namespace plugslam::io {
namespace {

using Cdr = plugslam::testing::CdrWriter;

std::string imageMsg(double t, const std::string& frame, int w, int h, const std::string& enc,
                     int bytes_per_pixel, const std::vector<uint8_t>& data) {
  Cdr c;
  c.header(t, frame).put<uint32_t>(h).put<uint32_t>(w).str(enc).put<uint8_t>(0);
  c.put<uint32_t>(static_cast<uint32_t>(w * bytes_per_pixel)).blob(data);
  return c.text();
}

std::string compressedMsg(double t, const std::string& frame, const std::string& format,
                          const std::vector<uint8_t>& data) {
  Cdr c;
  c.header(t, frame).str(format).blob(data);
  return c.text();
}

// A pinhole CameraInfo; `tx` is P[3] (-fx * baseline for a rectified right camera).
std::string cameraInfoMsg(const std::string& frame, int w, int h, double f, double tx,
                          std::vector<double> d = {}) {
  Cdr c;
  c.header(0.0, frame).put<uint32_t>(h).put<uint32_t>(w).str("plumb_bob");
  c.put<uint32_t>(static_cast<uint32_t>(d.size()));
  for (double v : d) c.put<double>(v);
  for (double v : {f, 0.0, w / 2.0, 0.0, f, h / 2.0, 0.0, 0.0, 1.0}) c.put<double>(v);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}) c.put<double>(v);
  for (double v : {f, 0.0, w / 2.0, tx, 0.0, f, h / 2.0, 0.0, 0.0, 0.0, 1.0, 0.0}) c.put<double>(v);
  c.put<uint32_t>(1).put<uint32_t>(1);
  for (int i = 0; i < 4; ++i) c.put<uint32_t>(0);
  c.put<uint8_t>(0);
  return c.text();
}

// base_link -> camera_optical: 0.2 m forward, 1 m up, optical axes (z forward, x right, y down).
std::string tfStaticMsg() {
  Cdr c;
  c.put<uint32_t>(1).header(0.0, "base_link").str("camera_optical");
  for (double v : {0.2, 0.0, 1.0}) c.put<double>(v);
  for (double v : {-0.5, 0.5, -0.5, 0.5}) c.put<double>(v);
  return c.text();
}

mcap::WriterOptions ros2Profile() {
  mcap::WriterOptions o;
  o.profile = "ros2";
  return o;
}

struct BagWriter {
  explicit BagWriter(const std::string& path) : w(path, ros2Profile()) {}
  void add(const std::string& topic, const char* type, uint64_t ns, const std::string& data) {
    if (!channels.count(topic)) {
      const uint16_t schema = w.addSchema(type, "ros2msg", "");
      channels[topic] = w.addChannel(schema, topic, "cdr");
    }
    w.write(channels[topic], ns, ns, data.data(), data.size());
  }
  mcap::Writer w;
  std::map<std::string, uint16_t> channels;
};

uint64_t ns(double t) { return static_cast<uint64_t>(std::llround(t * 1e9)); }

std::vector<uint8_t> pattern(int w, int h, int channels, int seed) {
  std::vector<uint8_t> v(static_cast<size_t>(w * h * channels));
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<uint8_t>((i * 7 + seed * 31) % 251);
  return v;
}

constexpr int kW = 8, kH = 6;

// A stereo bag of 5 pairs at 10 Hz, the right image of pair 2 missing.
std::string stereoBag(const plugslam::testing::TempDir& dir) {
  const std::string path = dir.file("stereo.mcap");
  BagWriter b(path);
  b.add("/tf_static", kRos2TfMessage, ns(1.0), tfStaticMsg());
  b.add("/left/camera_info", kRos2CameraInfo, ns(1.0), cameraInfoMsg("camera_optical", kW, kH, 100, 0));
  b.add("/right/camera_info", kRos2CameraInfo, ns(1.0),
        cameraInfoMsg("camera_right_optical", kW, kH, 100, -100 * 0.25));
  for (int i = 0; i < 5; ++i) {
    const double t = 1.0 + 0.1 * i;
    b.add("/left/image", kRos2Image, ns(t), imageMsg(t, "camera_optical", kW, kH, "mono8", 1, pattern(kW, kH, 1, i)));
    if (i != 2)
      b.add("/right/image", kRos2Image, ns(t),
            imageMsg(t, "camera_right_optical", kW, kH, "mono8", 1, pattern(kW, kH, 1, 100 + i)));
  }
  b.w.close();
  return path;
}

// The source reading `path`'s cameras alone: `images` (topic:entry) and their `camera_info`.
void camerasConfig(Ros2BagSource& s, const std::string& path, std::vector<std::string> images,
                   std::vector<std::string> camera_info) {
  s.path = path;
  s.scans = std::vector<std::string>{};
  s.odometry = "";
  s.images = std::move(images);
  s.camera_info = std::move(camera_info);
}

void stereoConfig(Ros2BagSource& s, const std::string& path) {
  camerasConfig(s, path, {"/left/image:left", "/right/image:right"},
                {"/left/camera_info", "/right/camera_info"});
}

std::vector<Frame> readAll(Source& s) {
  std::vector<Frame> out;
  Frame f;
  while (s.next(f)) {
    out.push_back(std::move(f));
    f = Frame{};
  }
  return out;
}

// The InputError that reading `s` to its end throws; "" (and a failure) when none does.
std::string readError(Source& s) {
  try {
    readAll(s);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(Ros2Camera, AStereoPairGivesSynchronisedFramesAndTheRectifiedCalibration) {
  plugslam::testing::TempDir dir("ros2cam");
  Ros2BagSource s;
  stereoConfig(s, stereoBag(dir));
  s.configure();
  const auto frames = readAll(s);
  ASSERT_EQ(frames.size(), 4u);  // pair 2 has no right image: dropped
  EXPECT_EQ(s.framesDropped(), 1u);
  const Image& left = frames[2].raw.get<Image>("left");  // the pair at 1.3 s
  EXPECT_NEAR(frames[2].stamp, 1.3, 1e-9);
  EXPECT_EQ(left.width, kW);
  EXPECT_EQ(left.channels, 1);
  EXPECT_EQ(left.data, pattern(kW, kH, 1, 3));
  EXPECT_EQ(frames[2].raw.get<Image>("right").data, pattern(kW, kH, 1, 103));
  const CameraInfo& c = frames[0].raw.get<CameraInfo>("camera");
  EXPECT_EQ(c.fx, 100);
  EXPECT_EQ(c.cx, kW / 2.0);
  EXPECT_EQ(c.distortion.model, Distortion::Model::kNone);
  EXPECT_NEAR(c.baseline, 0.25, 1e-12);
  ASSERT_TRUE(c.second.has_value());
  EXPECT_NEAR(c.second_pose.translation().x(), 0.25, 1e-12);
  // The mount from /tf_static: the optical z axis along the robot's x, origin 0.2 m ahead, 1 m up.
  EXPECT_NEAR(c.mount.translation().x(), 0.2, 1e-12);
  EXPECT_NEAR(c.mount.translation().z(), 1.0, 1e-12);
  EXPECT_NEAR((c.mount.linear().col(2) - Eigen::Vector3d::UnitX()).norm(), 0, 1e-12);
  EXPECT_NEAR((c.mount.linear().col(0) + Eigen::Vector3d::UnitY()).norm(), 0, 1e-12);
  const auto provided = s.provides();
  EXPECT_EQ(provided.size(), 3u);
}

TEST(Ros2Camera, TheConfigsMountWinsOverTfStatic) {
  plugslam::testing::TempDir dir("ros2cam");
  Ros2BagSource s;
  stereoConfig(s, stereoBag(dir));
  s.camera_mount = std::vector<double>{1, 2, 3, 0, 0, 0};
  s.configure();
  EXPECT_EQ(s.calibration().mount.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(Ros2Camera, RgbdColourAndDepthInBothEncodings) {
  for (const std::string enc : {"16UC1", "32FC1"}) {
    plugslam::testing::TempDir dir("ros2cam");
    const std::string path = dir.file("rgbd.mcap");
    {
      BagWriter b(path);
      b.add("/camera/color/camera_info", kRos2CameraInfo, ns(2.0),
            cameraInfoMsg("camera_optical", kW, kH, 50, 0));
      for (int i = 0; i < 3; ++i) {
        const double t = 2.0 + i / 30.0;
        // bgr8: the source gives RGB.
        b.add("/camera/color/image_raw", kRos2Image, ns(t),
              imageMsg(t, "camera_optical", kW, kH, "bgr8", 3, pattern(kW, kH, 3, i)));
        std::vector<uint8_t> depth;
        for (int p = 0; p < kW * kH; ++p) {
          if (enc == "16UC1") {
            const uint16_t mm = p == 0 ? 0 : static_cast<uint16_t>(1000 + 10 * p);
            depth.push_back(static_cast<uint8_t>(mm & 0xff));
            depth.push_back(static_cast<uint8_t>(mm >> 8));
          } else {
            const float m = p == 0 ? std::nanf("") : 1.0f + 0.01f * static_cast<float>(p);
            uint8_t raw[4];
            std::memcpy(raw, &m, 4);
            depth.insert(depth.end(), raw, raw + 4);
          }
        }
        // Depth 5 ms after colour, as a driver's two streams are.
        b.add("/camera/depth/image_raw", kRos2Image, ns(t + 0.005),
              imageMsg(t + 0.005, "camera_optical", kW, kH, enc, enc == "16UC1" ? 2 : 4, depth));
      }
      b.w.close();
    }
    Ros2BagSource s;
    camerasConfig(s, path, {"/camera/color/image_raw:rgb"}, {"/camera/color/camera_info"});
    s.depth = "/camera/depth/image_raw:depth";
    s.sync_tolerance = 0.01;
    s.configure();
    const auto frames = readAll(s);
    ASSERT_EQ(frames.size(), 3u) << enc;
    const Image& rgb = frames[1].raw.get<Image>("rgb");
    const auto bgr = pattern(kW, kH, 3, 1);
    EXPECT_EQ(rgb.channels, 3);
    EXPECT_EQ(rgb.at(1, 0, 0), bgr[5]);
    EXPECT_EQ(rgb.at(1, 0, 2), bgr[3]);
    const DepthImage& d = frames[1].raw.get<DepthImage>("depth");
    EXPECT_EQ(d.at(0, 0), 0.0f) << enc << ": no reading";
    EXPECT_NEAR(d.at(3, 1), enc == "16UC1" ? 1.11 : 1.11, 1e-6) << enc;
    const CameraInfo& c = frames[0].raw.get<CameraInfo>("camera");
    ASSERT_TRUE(c.second.has_value());  // registered: the colour pinhole
    EXPECT_EQ(c.second->fx, 50);
    EXPECT_EQ(c.baseline, 0);
  }
}

std::vector<uint8_t> pngBytes(const plugslam::testing::TempDir& dir, int channels) {
  Image im;
  im.resize(kW, kH, channels);
  im.data = pattern(kW, kH, channels, 9);
  writePng(dir.file("im.png"), im);
  return readFileBytes(dir.file("im.png"));
}

// One compressed colour camera; frame 1's image is `bad` when given.
std::string compressedBag(const plugslam::testing::TempDir& dir, const std::vector<uint8_t>& bad) {
  const std::string path = dir.file("compressed.mcap");
  BagWriter b(path);
  b.add("/cam/camera_info", kRos2CameraInfo, ns(3.0), cameraInfoMsg("cam", kW, kH, 50, 0));
  const auto png = pngBytes(dir, 3);
  for (int i = 0; i < 3; ++i)
    b.add("/cam/image/compressed", kRos2CompressedImage, ns(3.0 + 0.1 * i),
          compressedMsg(3.0 + 0.1 * i, "cam", "png", i == 1 && !bad.empty() ? bad : png));
  b.w.close();
  return path;
}

void compressedConfig(Ros2BagSource& s, const std::string& path) {
  camerasConfig(s, path, {"/cam/image/compressed:rgb"}, {"/cam/camera_info"});
}

TEST(Ros2Camera, ACompressedImageDecodesAsTheFileWould) {
  plugslam::testing::TempDir dir("ros2cam");
  Ros2BagSource s;
  compressedConfig(s, compressedBag(dir, {}));
  s.configure();
  const auto frames = readAll(s);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[1].raw.get<Image>("rgb").data, readImageFile(dir.file("im.png")).data);
  EXPECT_FALSE(frames[0].raw.get<CameraInfo>("camera").second.has_value());  // mono
}

TEST(Ros2Camera, AnUndecodableCompressedImageNamesFileTopicAndOffset) {
  plugslam::testing::TempDir dir("ros2cam");
  auto cut = pngBytes(dir, 3);
  cut.resize(cut.size() / 2);
  const std::string path = compressedBag(dir, cut);
  Ros2BagSource s;
  compressedConfig(s, path);
  s.configure();
  const std::string what = readError(s);
  EXPECT_NE(what.find(path), std::string::npos) << what;
  EXPECT_NE(what.find("/cam/image/compressed"), std::string::npos) << what;
  EXPECT_NE(what.find("byte offset"), std::string::npos) << what;
  // on_error: skip: the message is skipped, the others read.
  Ros2BagSource k;
  compressedConfig(k, path);
  k.on_error = "skip";
  k.configure();
  EXPECT_EQ(readAll(k).size(), 2u);
  EXPECT_EQ(k.skippedImages(), 1u);
}

TEST(Ros2Camera, AnImageOfAnotherSizeThanItsCameraIsAnError) {
  plugslam::testing::TempDir dir("ros2cam");
  const std::string path = dir.file("size.mcap");
  {
    BagWriter b(path);
    b.add("/cam/camera_info", kRos2CameraInfo, ns(1), cameraInfoMsg("cam", kW + 2, kH, 50, 0));
    b.add("/cam/image", kRos2Image, ns(1), imageMsg(1, "cam", kW, kH, "mono8", 1, pattern(kW, kH, 1, 0)));
    b.w.close();
  }
  Ros2BagSource s;
  camerasConfig(s, path, {"/cam/image:left"}, {"/cam/camera_info"});
  s.configure();
  const std::string what = readError(s);
  EXPECT_NE(what.find("/cam/image"), std::string::npos) << what;
  EXPECT_NE(what.find("8x6, its camera's is 10x6"), std::string::npos) << what;
}

TEST(Ros2Camera, EncodingsAndLayoutsThatDoNotFitAreNamed) {
  ImageMsg m;
  m.width = 2;
  m.height = 2;
  m.step = 2;
  m.encoding = "bayer_rggb8";
  m.data.assign(4, 0);
  EXPECT_THROW(imageFromRos(m), ParseError);
  m.encoding = "16UC1";
  try {
    imageFromRos(m);
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("`depth`"), std::string::npos) << e.what();
  }
  m.encoding = "mono8";
  m.data.assign(3, 0);  // step * height = 4
  EXPECT_THROW(imageFromRos(m), ParseError);
  m.encoding = "rgb8";
  m.data.assign(4, 0);  // step 2 < 2 pixels of 3 bytes
  EXPECT_THROW(imageFromRos(m), ParseError);
  m.encoding = "mono8";
  EXPECT_THROW(depthFromRos(m), ParseError);
  // mono16 keeps the high byte in either byte order.
  m.encoding = "mono16";
  m.step = 4;
  m.data = {0x34, 0x12, 0xff, 0x00, 0, 0, 0, 0};
  EXPECT_EQ(imageFromRos(m).data[0], 0x12);
  m.is_bigendian = true;
  EXPECT_EQ(imageFromRos(m).data[0], 0x34);
  CompressedImageMsg c;
  c.format = "png";
  c.data = {1, 2, 3};
  EXPECT_THROW(imageFromRos(c), ParseError);
}

TEST(Ros2Camera, TheCameraInfoPinholeAndDistortion) {
  CameraInfoMsg m;
  m.width = 640;
  m.height = 480;
  m.k = {500, 0, 320, 0, 501, 240, 0, 0, 1};
  m.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.p = {480, 0, 322, 0, 0, 481, 238, 0, 0, 0, 1, 0};
  m.distortion_model = "plumb_bob";
  m.d = {0.1, -0.2, 0.001, 0.002, 0.05};
  EXPECT_FALSE(isRectifiedCamera(m));
  CameraIntrinsics raw = intrinsicsFromRos(m, false);
  EXPECT_EQ(raw.fx, 500);
  EXPECT_EQ(raw.distortion.model, Distortion::Model::kRadialTangential);
  EXPECT_EQ(raw.distortion.coefficients.size(), 5u);
  CameraIntrinsics rect = intrinsicsFromRos(m, true);
  EXPECT_EQ(rect.fx, 480);
  EXPECT_EQ(rect.cy, 238);
  EXPECT_EQ(rect.distortion.model, Distortion::Model::kNone);
  m.d = {0.1, 0.2, 0.3};
  EXPECT_THROW(intrinsicsFromRos(m, false), ParseError);
  m.distortion_model = "unknown_model";
  EXPECT_THROW(intrinsicsFromRos(m, false), ParseError);
  m.d = {};
  m.k[0] = 0;
  EXPECT_THROW(intrinsicsFromRos(m, false), ParseError);
}

TEST(Ros2Camera, BadCameraConfigsAreParamErrors) {
  plugslam::testing::TempDir dir("ros2cam");
  const std::string path = stereoBag(dir);
  Ros2BagSource s;
  stereoConfig(s, path);
  s.camera_info = std::vector<std::string>{"/left/camera_info"};
  EXPECT_THROW(s.configure(), ParamError);  // a pair needs both
  stereoConfig(s, path);
  s.camera_info = std::vector<std::string>{"/left/camera_info", "/nope"};
  EXPECT_THROW(s.configure(), InputError);  // not in the bag
  stereoConfig(s, path);
  s.images = std::vector<std::string>{"/left/camera_info:left"};
  s.camera_info = std::vector<std::string>{"/left/camera_info"};
  EXPECT_THROW(s.configure(), InputError);  // a CameraInfo topic is no image
}

}  // namespace
}  // namespace plugslam::io
