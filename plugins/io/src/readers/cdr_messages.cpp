#include "readers/cdr_messages.h"

#include <cstring>

#include "plugslam/errors.h"
#include "readers/message_layouts.h"

namespace plugslam {
namespace io {

namespace {

// Bounds-checked CDR cursor; offsets in messages count from the start of the message (the
// encapsulation header included), alignment from its end.
class Cdr {
 public:
  Cdr(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {
    need(4, "the encapsulation header");
    // 0x0000 CDR_BE, 0x0001 CDR_LE (ROS 2's plain CDR); the options bytes are ignored.
    if (data_[0] != 0 || data_[1] > 1) {
      fail("encapsulation " + std::to_string(data_[0]) + "," + std::to_string(data_[1]) +
           " (expected CDR: 0,0 big or 0,1 little endian)");
    }
    little_ = data_[1] == 1;
    pos_ = 4;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw ParseError("CDR message", 0, "byte " + std::to_string(pos_) + " of the message: " + what);
  }
  void need(std::size_t n, const char* what) const {
    if (n > size_ - pos_) {
      fail(std::string(what) + " needs " + std::to_string(n) + " bytes but only " +
           std::to_string(size_ - pos_) + " remain (message truncated or of another type)");
    }
  }
  void align(std::size_t n) {
    const std::size_t rel = pos_ - 4;
    const std::size_t pad = (n - rel % n) % n;
    if (pad > size_ - pos_) return;  // the next read reports the shortage
    pos_ += pad;
  }
  template <typename T>
  T uint(const char* what) {
    align(sizeof(T));
    need(sizeof(T), what);
    T v = 0;
    for (std::size_t k = 0; k < sizeof(T); ++k) {
      const std::size_t shift = little_ ? k : sizeof(T) - 1 - k;
      v |= static_cast<T>(static_cast<T>(data_[pos_ + k]) << (8 * shift));
    }
    pos_ += sizeof(T);
    return v;
  }
  std::uint8_t u8(const char* what) {
    need(1, what);
    return data_[pos_++];
  }
  std::uint32_t u32(const char* what) { return uint<std::uint32_t>(what); }
  double f32(const char* what) {
    const std::uint32_t bits = uint<std::uint32_t>(what);
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
  }
  double f64(const char* what) {
    const std::uint64_t bits = uint<std::uint64_t>(what);
    double d;
    std::memcpy(&d, &bits, 8);
    return d;
  }
  // A CDR string: uint32 length including the terminating NUL, the bytes, the NUL.
  std::string str(const char* what) {
    const std::uint32_t n = u32(what);
    need(n, what);
    std::size_t len = n;
    if (len > 0 && data_[pos_ + len - 1] == 0) --len;
    std::string s(reinterpret_cast<const char*>(data_ + pos_), len);
    pos_ += n;
    return s;
  }
  std::uint32_t count(std::size_t element, const char* what) {
    const std::uint32_t n = u32(what);
    // Checked against the bytes present before anything is allocated.
    align(element);
    need(std::size_t{n} * element, what);
    return n;
  }
  void f32Array(std::vector<double>& out, const char* what) {
    const std::uint32_t n = count(4, what);
    out.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) out[i] = f32(what);
  }
  void f64Seq(std::vector<double>& out, const char* what) {
    const std::uint32_t n = count(8, what);
    out.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) out[i] = f64(what);
  }
  void bytes(std::vector<std::uint8_t>& out, const char* what) {
    const std::uint32_t n = count(1, what);
    out.assign(data_ + pos_, data_ + pos_ + n);
    pos_ += n;
  }
  template <std::size_t N>
  void f64Array(std::array<double, N>& out, const char* what) {
    for (double& v : out) v = f64(what);
  }
  void header(RosHeader& h) {
    h.seq = 0;  // ROS 2 headers carry no sequence number
    const std::uint32_t sec = u32("header.stamp.sec");
    h.stamp.sec = sec;  // int32 on the wire: stamps before 1970 do not occur in bags
    h.stamp.nsec = u32("header.stamp.nanosec");
    h.frame_id = str("header.frame_id");
  }
  void finish() const {
    // CDR pads a message to a multiple of 4 bytes at most: more left over is another type.
    if (size_ - pos_ >= 4) {
      fail(std::to_string(size_ - pos_) +
           " bytes left over after the last field (message of another type?)");
    }
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool little_ = true;
};

void transform(Cdr& c, TransformMsg& t) {
  c.header(t.header);
  t.child_frame_id = c.str("child_frame_id");
  c.f64Array(t.translation, "transform.translation");
  c.f64Array(t.rotation, "transform.rotation");
}

void tf(Cdr& c, TfMsg& m) {
  // Each element is at least a header and two strings: bound the count by the bytes present.
  const std::uint32_t n = c.count(1, "transforms");
  m.transforms.resize(n);
  for (auto& t : m.transforms) transform(c, t);
}

// The fields Image and CameraInfo start with.
template <typename Msg>
void headerAndSize(Cdr& c, Msg& m) {
  c.header(m.header);
  m.height = c.u32("height");
  m.width = c.u32("width");
}

void image(Cdr& c, ImageMsg& m) {
  headerAndSize(c, m);
  m.encoding = c.str("encoding");
  m.is_bigendian = c.u8("is_bigendian") != 0;
  m.step = c.u32("step");
  c.bytes(m.data, "data");
}

void compressedImage(Cdr& c, CompressedImageMsg& m) {
  c.header(m.header);
  m.format = c.str("format");
  c.bytes(m.data, "data");
}

void cameraInfo(Cdr& c, CameraInfoMsg& m) {
  headerAndSize(c, m);
  m.distortion_model = c.str("distortion_model");
  c.f64Seq(m.d, "d");
  c.f64Array(m.k, "k");
  c.f64Array(m.r, "r");
  c.f64Array(m.p, "p");
  m.binning_x = c.u32("binning_x");
  m.binning_y = c.u32("binning_y");
  for (auto& v : m.roi) v = c.u32("roi");
  m.do_rectify = c.u8("roi.do_rectify") != 0;
}

}  // namespace

void decodeCdr(const std::uint8_t* data, std::size_t size, LaserScanMsg& m) {
  layout::decodeWhole<Cdr>(data, size, m, layout::laserScan<Cdr>);
}

void decodeCdr(const std::uint8_t* data, std::size_t size, OdometryMsg& m) {
  layout::decodeWhole<Cdr>(data, size, m, layout::odometry<Cdr>);
}

void decodeCdr(const std::uint8_t* data, std::size_t size, ImageMsg& m) {
  layout::decodeWhole<Cdr>(data, size, m, image);
}

void decodeCdr(const std::uint8_t* data, std::size_t size, CompressedImageMsg& m) {
  layout::decodeWhole<Cdr>(data, size, m, compressedImage);
}

void decodeCdr(const std::uint8_t* data, std::size_t size, CameraInfoMsg& m) {
  layout::decodeWhole<Cdr>(data, size, m, cameraInfo);
}

void decodeCdr(const std::uint8_t* data, std::size_t size, TfMsg& m) {
  layout::decodeWhole<Cdr>(data, size, m, tf);
}

}  // namespace io
}  // namespace plugslam
