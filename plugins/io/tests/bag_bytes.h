#pragma once
// Byte-level builders for ROS bag v2.0 records, shared by the io tests that write small bags.
#include <cstdint>
#include <cstring>
#include <string>

namespace plugslam::io::bagbytes {

/// Little-endian encodings and length-prefixed strings as bag records use them.
inline std::string u32(std::uint32_t v) {
  std::string s(4, '\0');
  for (int i = 0; i < 4; ++i) s[i] = static_cast<char>((v >> (8 * i)) & 0xff);
  return s;
}
inline std::string u64(std::uint64_t v) { return u32(static_cast<std::uint32_t>(v)) + u32(v >> 32); }
inline std::string f32(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return u32(b);
}
inline std::string f64(double d) {
  std::uint64_t b;
  std::memcpy(&b, &d, 8);
  return u64(b);
}
inline std::string str(const std::string& s) { return u32(static_cast<std::uint32_t>(s.size())) + s; }
inline std::string field(const std::string& name, const std::string& value) {
  return str(name + "=" + value);
}
inline std::string record(const std::string& header, const std::string& data) {
  return str(header) + str(data);
}
inline std::string op(std::uint8_t o) { return field("op", std::string(1, static_cast<char>(o))); }
inline std::string connection(std::uint32_t id, const std::string& topic, const std::string& type,
                       const std::string& md5) {
  return record(op(7) + field("conn", u32(id)) + field("topic", topic),
                field("topic", topic) + field("type", type) + field("md5sum", md5) +
                    field("message_definition", "..."));
}

}  // namespace plugslam::io::bagbytes
