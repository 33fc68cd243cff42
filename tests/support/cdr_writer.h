#pragma once
// CDR (XCDR1) laid out by hand for the decoder tests: each primitive aligned to its size from the
// end of the 4-byte encapsulation header, in either byte order. Header-only.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace plugslam::testing {

/// Writes one CDR message: primitives, strings, byte blobs and a std_msgs/Header.
class CdrWriter {
 public:
  explicit CdrWriter(bool little = true) : little_(little) {
    bytes_ = {0, static_cast<uint8_t>(little ? 1 : 0), 0, 0};
  }
  template <typename T>
  CdrWriter& put(T v) {
    while ((bytes_.size() - 4) % sizeof(T) != 0) bytes_.push_back(0);
    uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));  // the machine is little-endian
    for (size_t k = 0; k < sizeof(T); ++k) bytes_.push_back(raw[little_ ? k : sizeof(T) - 1 - k]);
    return *this;
  }
  CdrWriter& str(const std::string& s) {
    put<uint32_t>(static_cast<uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
    return *this;
  }
  /// A uint8[] sequence: its length, then the bytes.
  CdrWriter& blob(const std::vector<uint8_t>& b) {
    put<uint32_t>(static_cast<uint32_t>(b.size()));
    bytes_.insert(bytes_.end(), b.begin(), b.end());
    return *this;
  }
  CdrWriter& header(int32_t sec, uint32_t nsec, const std::string& frame) {
    return put<int32_t>(sec).put<uint32_t>(nsec).str(frame);
  }
  /// A header stamped `t` seconds.
  CdrWriter& header(double t, const std::string& frame) {
    const auto sec = static_cast<int32_t>(std::floor(t));
    return header(sec, static_cast<uint32_t>(std::lround((t - sec) * 1e9)), frame);
  }
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  /// The message as a string of bytes (what an MCAP message record holds).
  std::string text() const { return {bytes_.begin(), bytes_.end()}; }

 private:
  bool little_;
  std::vector<uint8_t> bytes_;
};

}  // namespace plugslam::testing
