#pragma once
// Shared by the libFuzzer targets: the contract every parser must keep on arbitrary input is
// "return normally or throw plugslam::Error"; anything else (another exception type, a crash, a
// sanitizer report) is a finding. Exceptions of other types escape to libFuzzer, which reports
// them as a crash with the input.
#include <cstddef>
#include <cstdint>
#include <string>

namespace plugslam::fuzz {

/// The fuzzer input as a string.
inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace plugslam::fuzz
