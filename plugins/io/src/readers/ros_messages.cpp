#include "readers/ros_messages.h"

#include <cmath>
#include <cstring>

#include "plugslam/errors.h"
#include "readers/message_layouts.h"

namespace plugslam {
namespace io {

namespace {

// Bounds-checked little-endian cursor over one serialized message.
class Cursor {
 public:
  Cursor(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  void need(std::size_t n, const char* what) const {
    if (n > size_ - pos_) {
      throw ParseError("ROS message", 0,
                       "byte " + std::to_string(pos_) + " of the message: " + what + " needs " +
                           std::to_string(n) + " bytes but only " + std::to_string(size_ - pos_) +
                           " remain (message truncated or of another type)");
    }
  }
  std::uint32_t u32(const char* what) {
    need(4, what);
    const std::uint8_t* p = data_ + pos_;
    pos_ += 4;
    return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
           std::uint32_t{p[3]} << 24;
  }
  std::uint64_t u64(const char* what) {
    std::uint64_t lo = u32(what);
    std::uint64_t hi = u32(what);
    return lo | hi << 32;
  }
  double f32(const char* what) {
    std::uint32_t bits = u32(what);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
  double f64(const char* what) {
    std::uint64_t bits = u64(what);
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  std::string str(const char* what) {
    std::uint32_t n = u32(what);
    need(n, what);
    std::string s(reinterpret_cast<const char*>(data_ + pos_), n);
    pos_ += n;
    return s;
  }
  void f32Array(std::vector<double>& out, const char* what) {
    std::uint32_t n = u32(what);
    // The count is checked against the bytes present before anything is allocated.
    need(std::size_t{n} * 4, what);
    out.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) out[i] = f32(what);
  }
  void header(RosHeader& h) {
    h.seq = u32("header.seq");
    h.stamp.sec = u32("header.stamp.sec");
    h.stamp.nsec = u32("header.stamp.nsec");
    h.frame_id = str("header.frame_id");
  }
  void finish() const {
    if (pos_ != size_) {
      throw ParseError("ROS message", 0,
                       "byte " + std::to_string(pos_) +
                           " of the message: " + std::to_string(size_ - pos_) +
                           " bytes left over after the last field (message of another type?)");
    }
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_{0};
};

void checkType(const RosbagReader& bag, const RosbagMessage& m, RosType expected,
               const char* other_name = nullptr) {
  const char* type = expected.name;
  const char* md5 = expected.md5;
  if (!m.connection) throw ParseError(bag.path(), 0, "message without a connection");
  const RosbagConnection& c = *m.connection;
  if (c.type != type && !(other_name && c.type == other_name)) {
    throw ParseError(bag.path(), 0,
                     "topic " + c.topic + " has type " + c.type + "; expected " + type);
  }
  if (!c.md5sum.empty() && c.md5sum != "*" && c.md5sum != md5) {
    throw ParseError(bag.path(), 0,
                     "topic " + c.topic + " (" + type + ") has md5sum " + c.md5sum + "; expected " +
                         md5 + " (another version of the message definition)");
  }
}

template <typename Msg, typename Fn>
void decodeWithContext(const RosbagReader& bag, const RosbagMessage& m, Msg& out, Fn fn) {
  try {
    fn(m.data.data(), m.data.size(), out);
  } catch (const ParseError& e) {
    throw ParseError(bag.path(), 0,
                     "message on " + m.connection->topic + " in the record at byte offset " +
                         std::to_string(m.file_offset) + ": " + e.message());
  }
}

}  // namespace

double OdometryMsg::yaw() const {
  const double x = orientation[0], y = orientation[1], z = orientation[2], w = orientation[3];
  return std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
}

void decodeTf(const std::uint8_t* data, std::size_t size, TfMsg& out) {
  Cursor c(data, size);
  const std::uint32_t n = c.u32("transforms");
  // A transform is at least its header (3 x 4 bytes + the frame's length), the child's length
  // and 7 doubles: the count is checked against the bytes present before anything is allocated.
  constexpr std::size_t kMinTransform = 12 + 4 + 4 + 7 * 8;
  c.need(std::size_t{n} * kMinTransform, "transforms");
  out.transforms.resize(n);
  for (TransformMsg& t : out.transforms) {
    c.header(t.header);
    t.child_frame_id = c.str("child_frame_id");
    for (double& v : t.translation) v = c.f64("transform.translation");
    for (double& v : t.rotation) v = c.f64("transform.rotation");
  }
  c.finish();
}

void decodeLaserScan(const std::uint8_t* data, std::size_t size, LaserScanMsg& out) {
  layout::decodeWhole<Cursor>(data, size, out, layout::laserScan<Cursor>);
}

void decodeOdometry(const std::uint8_t* data, std::size_t size, OdometryMsg& out) {
  layout::decodeWhole<Cursor>(data, size, out, layout::odometry<Cursor>);
}

void decodeLaserScan(const RosbagReader& bag, const RosbagMessage& message, LaserScanMsg& out) {
  checkType(bag, message, kRosLaserScan);
  decodeWithContext(bag, message, out, [](const std::uint8_t* d, std::size_t n, LaserScanMsg& o) {
    decodeLaserScan(d, n, o);
  });
}

void decodeOdometry(const RosbagReader& bag, const RosbagMessage& message, OdometryMsg& out) {
  checkType(bag, message, kRosOdometry);
  decodeWithContext(bag, message, out, [](const std::uint8_t* d, std::size_t n, OdometryMsg& o) {
    decodeOdometry(d, n, o);
  });
}

void decodeTf(const RosbagReader& bag, const RosbagMessage& message, TfMsg& out) {
  checkType(bag, message, kRosTfMessage, kTfMessageOldType);
  decodeWithContext(bag, message, out,
                    [](const std::uint8_t* d, std::size_t n, TfMsg& o) { decodeTf(d, n, o); });
}

}  // namespace io
}  // namespace plugslam
