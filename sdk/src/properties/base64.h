#pragma once
// Base64 for byte blobs in archives (pixels, descriptors): the archive has no byte type, and a
// string is compact in the binary back-end and valid UTF-8 in the text one. SDK-internal.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// The n bytes at p as base64 text (with '=' padding).
std::string toBase64(const uint8_t* p, size_t n);
/// Decodes base64 text into `out`; false on a character outside the alphabet or a bad length.
bool fromBase64(const std::string& s, std::vector<uint8_t>& out);

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
