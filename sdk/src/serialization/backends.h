#pragma once
// The archive back-ends behind makeOutArchive / makeInArchive (SDK-internal).
#include <iosfwd>
#include <memory>
#include <string>

#include "plugslam/archive.h"

namespace plugslam {
inline namespace abi_v1 {
namespace serialization {

/// The 4 bytes every binary archive starts with.
inline constexpr char kBinaryMagic[4] = {'P', 'L', 'S', 'B'};
/// The binary format version this build writes and reads.
inline constexpr std::uint32_t kBinaryVersion = 1;
/// The text format version this build writes and reads.
inline constexpr int kTextVersion = 1;
/// Deepest nesting of objects/arrays a reader accepts (guards the stack against crafted input).
inline constexpr int kMaxDepth = 256;

std::unique_ptr<OutArchive> makeBinaryOut(std::ostream& out);
std::unique_ptr<InArchive> makeBinaryIn(std::istream& in, const std::string& source);
std::unique_ptr<OutArchive> makeTextOut(std::ostream& out);
std::unique_ptr<InArchive> makeTextIn(std::istream& in, const std::string& source);

/// CRC-32 (IEEE 802.3), continuing from `crc` (0 to start).
std::uint32_t crc32(std::uint32_t crc, const void* data, std::size_t n);

}  // namespace serialization
}  // namespace abi_v1
}  // namespace plugslam
