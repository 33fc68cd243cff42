// Byte layout of the MCAP records (https://mcap.dev/spec).
#include "plugslam/mcap/records.h"

#include <array>

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

namespace {

// CRC-32 (IEEE, reflected, as zlib and the MCAP spec) by slicing-by-8: table k gives the CRC of a
// byte followed by k zero bytes, so eight bytes are folded per step. A linear MCAP scan CRCs
// every byte of the file; one table lookup per byte held it near 230 MB/s, this about 4x that.
using CrcTables = std::array<std::array<uint32_t, 256>, 8>;
CrcTables makeCrcTables() {
  CrcTables t{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[0][i] = c;
  }
  for (size_t k = 1; k < 8; ++k)
    for (uint32_t i = 0; i < 256; ++i) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xFF];
  return t;
}

uint32_t load32le(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
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
  static const CrcTables t = makeCrcTables();
  const auto* p = static_cast<const uint8_t*>(data);
  crc = ~crc;
  for (; size >= 8; size -= 8, p += 8) {
    const uint32_t lo = crc ^ load32le(p);
    const uint32_t hi = load32le(p + 4);
    crc = t[7][lo & 0xFF] ^ t[6][(lo >> 8) & 0xFF] ^ t[5][(lo >> 16) & 0xFF] ^ t[4][lo >> 24] ^
          t[3][hi & 0xFF] ^ t[2][(hi >> 8) & 0xFF] ^ t[1][(hi >> 16) & 0xFF] ^ t[0][hi >> 24];
  }
  for (; size > 0; --size, ++p) crc = t[0][(crc ^ *p) & 0xFF] ^ (crc >> 8);
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

namespace {

// Little-endian readers of the same types, bounds-checked against the content.
class Cursor {
 public:
  Cursor(const uint8_t* p, size_t n) : p_(p), n_(n) {}
  template <typename T>
  T uint(const char* field) {
    need(sizeof(T), field);
    T v = 0;
    for (size_t k = 0; k < sizeof(T); ++k) v |= static_cast<T>(T{p_[i_ + k]} << (8 * k));
    i_ += sizeof(T);
    return v;
  }
  std::string str(const char* field) {
    const size_t at = i_;
    const auto len = uint<uint32_t>(field);
    if (len > n_ - i_) {
      throw RecordError(at, std::string(field) + " of " + std::to_string(len) +
                                " bytes exceeds the " + std::to_string(n_ - i_) +
                                " bytes left in the record");
    }
    std::string s(reinterpret_cast<const char*>(p_ + i_), len);
    i_ += len;
    return s;
  }
  std::vector<std::pair<uint16_t, uint64_t>> u16u64Map(const char* field) {
    const size_t at = i_;
    const auto len = uint<uint32_t>(field);
    if (len > n_ - i_ || len % 10 != 0) {
      throw RecordError(at, std::string(field) + ": map of " + std::to_string(len) +
                                " bytes (a multiple of 10 within the record expected)");
    }
    std::vector<std::pair<uint16_t, uint64_t>> out;
    for (size_t k = 0; k < len / 10; ++k) {
      const auto key = uint<uint16_t>(field);
      out.emplace_back(key, uint<uint64_t>(field));
    }
    return out;
  }
  size_t at() const { return i_; }
  size_t left() const { return n_ - i_; }
  void skip(size_t n, const char* field) {
    need(n, field);
    i_ += n;
  }

 private:
  void need(size_t k, const char* field) const {
    if (n_ - i_ < k) {
      throw RecordError(i_, std::string(field) + " needs " + std::to_string(k) + " bytes, " +
                                std::to_string(n_ - i_) + " left in the record");
    }
  }
  const uint8_t* p_;
  size_t n_, i_ = 0;
};

}  // namespace

void parseRecord(const uint8_t* p, size_t n, Header& r) {
  Cursor c(p, n);
  r.profile = c.str("header profile");
  r.library = c.str("header library");
}

void parseRecord(const uint8_t* p, size_t n, Footer& r) {
  Cursor c(p, n);
  r.summary_start = c.uint<uint64_t>("footer summary_start");
  r.summary_offset_start = c.uint<uint64_t>("footer summary_offset_start");
  r.summary_crc = c.uint<uint32_t>("footer summary_crc");
}

void parseRecord(const uint8_t* p, size_t n, Schema& r) {
  Cursor c(p, n);
  r.id = c.uint<uint16_t>("schema id");
  r.name = c.str("schema name");
  r.encoding = c.str("schema encoding");
  r.data = c.str("schema data");
}

void parseRecord(const uint8_t* p, size_t n, Channel& r) {
  Cursor c(p, n);
  r.id = c.uint<uint16_t>("channel id");
  r.schema_id = c.uint<uint16_t>("channel schema_id");
  r.topic = c.str("channel topic");
  r.message_encoding = c.str("channel message_encoding");
  const size_t at = c.at();
  const auto len = c.uint<uint32_t>("channel metadata");
  if (len > c.left()) throw RecordError(at, "channel metadata exceeds the record");
  Cursor m(p + c.at(), len);
  r.metadata.clear();
  while (m.left() > 0) {
    std::string key = m.str("channel metadata key");
    r.metadata.emplace_back(std::move(key), m.str("channel metadata value"));
  }
}

void parseRecord(const uint8_t* p, size_t n, ChunkIndex& r) {
  Cursor c(p, n);
  r.message_start_time = c.uint<uint64_t>("chunk index message_start_time");
  r.message_end_time = c.uint<uint64_t>("chunk index message_end_time");
  r.chunk_start_offset = c.uint<uint64_t>("chunk index chunk_start_offset");
  r.chunk_length = c.uint<uint64_t>("chunk index chunk_length");
  r.message_index_offsets = c.u16u64Map("chunk index message_index_offsets");
  r.message_index_length = c.uint<uint64_t>("chunk index message_index_length");
  r.compression = c.str("chunk index compression");
  r.compressed_size = c.uint<uint64_t>("chunk index compressed_size");
  r.uncompressed_size = c.uint<uint64_t>("chunk index uncompressed_size");
}

void parseRecord(const uint8_t* p, size_t n, Statistics& r) {
  Cursor c(p, n);
  r.message_count = c.uint<uint64_t>("statistics message_count");
  r.schema_count = c.uint<uint16_t>("statistics schema_count");
  r.channel_count = c.uint<uint32_t>("statistics channel_count");
  r.attachment_count = c.uint<uint32_t>("statistics attachment_count");
  r.metadata_count = c.uint<uint32_t>("statistics metadata_count");
  r.chunk_count = c.uint<uint32_t>("statistics chunk_count");
  r.message_start_time = c.uint<uint64_t>("statistics message_start_time");
  r.message_end_time = c.uint<uint64_t>("statistics message_end_time");
  r.channel_message_counts = c.u16u64Map("statistics channel_message_counts");
}

size_t parseMessage(const uint8_t* p, size_t n, MessageHeader& r) {
  Cursor c(p, n);
  r.channel_id = c.uint<uint16_t>("message channel_id");
  r.sequence = c.uint<uint32_t>("message sequence");
  r.log_time = c.uint<uint64_t>("message log_time");
  r.publish_time = c.uint<uint64_t>("message publish_time");
  return c.at();
}

size_t parseChunk(const uint8_t* p, size_t n, ChunkHeader& r) {
  Cursor c(p, n);
  r.message_start_time = c.uint<uint64_t>("chunk message_start_time");
  r.message_end_time = c.uint<uint64_t>("chunk message_end_time");
  r.uncompressed_size = c.uint<uint64_t>("chunk uncompressed_size");
  r.uncompressed_crc = c.uint<uint32_t>("chunk uncompressed_crc");
  r.compression = c.str("chunk compression");
  const size_t at = c.at();
  r.records_size = c.uint<uint64_t>("chunk records_size");
  if (r.records_size > c.left()) {
    throw RecordError(at, "chunk records of " + std::to_string(r.records_size) +
                              " bytes exceed the " + std::to_string(c.left()) +
                              " bytes left in the record");
  }
  return c.at();
}

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
