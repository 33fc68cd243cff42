// Byte layout of the MCAP records (https://mcap.dev/spec).
#include "plugslam/mcap/records.h"

#include <array>

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

namespace {

std::array<uint32_t, 256> makeCrcTable() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

// Little-endian appenders of the spec's serialization types.
void u8(std::string& o, uint8_t v) { o.push_back(static_cast<char>(v)); }
void u16(std::string& o, uint16_t v) {
  for (int i = 0; i < 2; ++i) o.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void u32(std::string& o, uint32_t v) {
  for (int i = 0; i < 4; ++i) o.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void u64(std::string& o, uint64_t v) {
  for (int i = 0; i < 8; ++i) o.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void str(std::string& o, const std::string& s) {
  u32(o, static_cast<uint32_t>(s.size()));
  o += s;
}
// A Map<uint16, uint64>: its uint32 byte length, then the pairs.
void u16u64Map(std::string& o, const std::vector<std::pair<uint16_t, uint64_t>>& map) {
  u32(o, static_cast<uint32_t>(map.size() * 10));
  for (const auto& [key, value] : map) {
    u16(o, key);
    u64(o, value);
  }
}
// Writes a uint32 byte-length prefix placeholder; returns where it is.
size_t beginLength32(std::string& o) {
  const size_t at = o.size();
  u32(o, 0);
  return at;
}
void endLength32(std::string& o, size_t at) {
  const auto n = static_cast<uint32_t>(o.size() - at - 4);
  for (int i = 0; i < 4; ++i) o[at + i] = static_cast<char>((n >> (8 * i)) & 0xFF);
}
// Opens a record: opcode and a uint64 length filled by endRecord.
size_t beginRecord(std::string& o, Op op) {
  u8(o, static_cast<uint8_t>(op));
  const size_t at = o.size();
  u64(o, 0);
  return at;
}
void endRecord(std::string& o, size_t at) {
  const uint64_t n = o.size() - at - 8;
  for (int i = 0; i < 8; ++i) o[at + i] = static_cast<char>((n >> (8 * i)) & 0xFF);
}

}  // namespace

uint32_t crc32(const void* data, size_t size, uint32_t crc) {
  static const std::array<uint32_t, 256> table = makeCrcTable();
  const auto* p = static_cast<const uint8_t*>(data);
  crc = ~crc;
  for (size_t i = 0; i < size; ++i) crc = table[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
  return ~crc;
}

void appendRecord(std::string& o, const Header& r) {
  const size_t at = beginRecord(o, Op::kHeader);
  str(o, r.profile);
  str(o, r.library);
  endRecord(o, at);
}

void appendRecord(std::string& o, const Footer& r) {
  const size_t at = beginRecord(o, Op::kFooter);
  u64(o, r.summary_start);
  u64(o, r.summary_offset_start);
  u32(o, r.summary_crc);
  endRecord(o, at);
}

void appendRecord(std::string& o, const Schema& r) {
  const size_t at = beginRecord(o, Op::kSchema);
  u16(o, r.id);
  str(o, r.name);
  str(o, r.encoding);
  str(o, r.data);  // uint32 length-prefixed bytes: the same layout as a string
  endRecord(o, at);
}

void appendRecord(std::string& o, const Channel& r) {
  const size_t at = beginRecord(o, Op::kChannel);
  u16(o, r.id);
  u16(o, r.schema_id);
  str(o, r.topic);
  str(o, r.message_encoding);
  const size_t map = beginLength32(o);
  for (const auto& [k, v] : r.metadata) {
    str(o, k);
    str(o, v);
  }
  endLength32(o, map);
  endRecord(o, at);
}

void appendRecord(std::string& o, const MessageIndex& r) {
  const size_t at = beginRecord(o, Op::kMessageIndex);
  u16(o, r.channel_id);
  u32(o, static_cast<uint32_t>(r.records.size() * 16));
  for (const auto& [time, offset] : r.records) {
    u64(o, time);
    u64(o, offset);
  }
  endRecord(o, at);
}

void appendRecord(std::string& o, const ChunkIndex& r) {
  const size_t at = beginRecord(o, Op::kChunkIndex);
  u64(o, r.message_start_time);
  u64(o, r.message_end_time);
  u64(o, r.chunk_start_offset);
  u64(o, r.chunk_length);
  u16u64Map(o, r.message_index_offsets);
  u64(o, r.message_index_length);
  str(o, r.compression);
  u64(o, r.compressed_size);
  u64(o, r.uncompressed_size);
  endRecord(o, at);
}

void appendRecord(std::string& o, const Statistics& r) {
  const size_t at = beginRecord(o, Op::kStatistics);
  u64(o, r.message_count);
  u16(o, r.schema_count);
  u32(o, r.channel_count);
  u32(o, r.attachment_count);
  u32(o, r.metadata_count);
  u32(o, r.chunk_count);
  u64(o, r.message_start_time);
  u64(o, r.message_end_time);
  u16u64Map(o, r.channel_message_counts);
  endRecord(o, at);
}

void appendRecord(std::string& o, const SummaryOffset& r) {
  const size_t at = beginRecord(o, Op::kSummaryOffset);
  u8(o, static_cast<uint8_t>(r.group_opcode));
  u64(o, r.group_start);
  u64(o, r.group_length);
  endRecord(o, at);
}

void appendDataEnd(std::string& o, uint32_t data_section_crc) {
  const size_t at = beginRecord(o, Op::kDataEnd);
  u32(o, data_section_crc);
  endRecord(o, at);
}

void appendMessage(std::string& o, const MessageHeader& h, const void* data, size_t size) {
  const size_t at = beginRecord(o, Op::kMessage);
  u16(o, h.channel_id);
  u32(o, h.sequence);
  u64(o, h.log_time);
  u64(o, h.publish_time);
  o.append(static_cast<const char*>(data), size);
  endRecord(o, at);
}

void appendChunk(std::string& o, ChunkHeader h, const std::string& records) {
  const size_t at = beginRecord(o, Op::kChunk);
  u64(o, h.message_start_time);
  u64(o, h.message_end_time);
  u64(o, h.uncompressed_size);
  u32(o, h.uncompressed_crc);
  str(o, h.compression);
  u64(o, records.size());
  o += records;
  endRecord(o, at);
}

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
