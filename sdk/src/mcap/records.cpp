// Byte layout of the MCAP records (https://mcap.dev/spec).
#include "plugslam/mcap/records.h"

#include <array>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

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

// Little-endian readers of the same types, bounds-checked against the content.
class Cursor {
 public:
  // `record` begins each field's name in messages ("footer" + " summary_start").
  Cursor(const uint8_t* p, size_t n, const char* record) : p_(p), n_(n), record_(record) {}
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
      throw RecordError(at, name(field) + " of " + std::to_string(len) + " bytes exceeds the " +
                                std::to_string(n_ - i_) + " bytes left in the record");
    }
    std::string s(reinterpret_cast<const char*>(p_ + i_), len);
    i_ += len;
    return s;
  }
  std::vector<std::pair<uint16_t, uint64_t>> u16u64Map(const char* field) {
    const size_t at = i_;
    const auto len = uint<uint32_t>(field);
    if (len > n_ - i_ || len % 10 != 0) {
      throw RecordError(at, name(field) + ": map of " + std::to_string(len) +
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
  std::string name(const char* field) const { return std::string(record_) + " " + field; }
  void need(size_t k, const char* field) const {
    if (n_ - i_ < k) {
      throw RecordError(i_, name(field) + " needs " + std::to_string(k) + " bytes, " +
                                std::to_string(n_ - i_) + " left in the record");
    }
  }
  const uint8_t* p_;
  size_t n_, i_ = 0;
  const char* record_;
};

// The two directions of a record's field list (below): Writer appends each field, Reader reads
// it back, each by the field's own type.
struct Writer {
  std::string& o;
  void operator()(uint16_t v, const char*) { u16(o, v); }
  void operator()(uint32_t v, const char*) { u32(o, v); }
  void operator()(uint64_t v, const char*) { u64(o, v); }
  void operator()(const std::string& v, const char*) { str(o, v); }
  void operator()(const std::vector<std::pair<uint16_t, uint64_t>>& v, const char*) {
    u16u64Map(o, v);
  }
};

struct Reader {
  Cursor& c;
  template <class T>
  void operator()(T& v, const char* field) {
    if constexpr (std::is_same_v<T, std::string>)
      v = c.str(field);
    else if constexpr (std::is_same_v<T, std::vector<std::pair<uint16_t, uint64_t>>>)
      v = c.u16u64Map(field);
    else
      v = c.uint<T>(field);
  }
};

// Each record's fields in their byte order, listed once for writing and reading (R is the record,
// const when written).
template <class Io, class R>
void headerFields(Io& io, R& r) {
  io(r.profile, "profile");
  io(r.library, "library");
}

template <class Io, class R>
void footerFields(Io& io, R& r) {
  io(r.summary_start, "summary_start");
  io(r.summary_offset_start, "summary_offset_start");
  io(r.summary_crc, "summary_crc");
}

template <class Io, class R>
void schemaFields(Io& io, R& r) {
  io(r.id, "id");
  io(r.name, "name");
  io(r.encoding, "encoding");
  io(r.data, "data");  // uint32 length-prefixed bytes: the same layout as a string
}

// The fields before the metadata map.
template <class Io, class R>
void channelFields(Io& io, R& r) {
  io(r.id, "id");
  io(r.schema_id, "schema_id");
  io(r.topic, "topic");
  io(r.message_encoding, "message_encoding");
}

template <class Io, class R>
void chunkIndexFields(Io& io, R& r) {
  io(r.message_start_time, "message_start_time");
  io(r.message_end_time, "message_end_time");
  io(r.chunk_start_offset, "chunk_start_offset");
  io(r.chunk_length, "chunk_length");
  io(r.message_index_offsets, "message_index_offsets");
  io(r.message_index_length, "message_index_length");
  io(r.compression, "compression");
  io(r.compressed_size, "compressed_size");
  io(r.uncompressed_size, "uncompressed_size");
}

template <class Io, class R>
void statisticsFields(Io& io, R& r) {
  io(r.message_count, "message_count");
  io(r.schema_count, "schema_count");
  io(r.channel_count, "channel_count");
  io(r.attachment_count, "attachment_count");
  io(r.metadata_count, "metadata_count");
  io(r.chunk_count, "chunk_count");
  io(r.message_start_time, "message_start_time");
  io(r.message_end_time, "message_end_time");
  io(r.channel_message_counts, "channel_message_counts");
}

// The fields before the message's data.
template <class Io, class R>
void messageFields(Io& io, R& r) {
  io(r.channel_id, "channel_id");
  io(r.sequence, "sequence");
  io(r.log_time, "log_time");
  io(r.publish_time, "publish_time");
}

// The fields before the records' size and the records.
template <class Io, class R>
void chunkFields(Io& io, R& r) {
  io(r.message_start_time, "message_start_time");
  io(r.message_end_time, "message_end_time");
  io(r.uncompressed_size, "uncompressed_size");
  io(r.uncompressed_crc, "uncompressed_crc");
  io(r.compression, "compression");
}

// A whole record whose content is what `fields` writes of r.
template <class R>
void appendFields(std::string& o, Op op, const R& r, void (*fields)(Writer&, const R&)) {
  const size_t at = beginRecord(o, op);
  Writer w{o};
  fields(w, r);
  endRecord(o, at);
}

// A record's content read into r by `fields`; messages name the `record`.
template <class R>
void parseFields(const uint8_t* p, size_t n, const char* record, R& r,
                 void (*fields)(Reader&, R&)) {
  Cursor c(p, n, record);
  Reader in{c};
  fields(in, r);
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
  appendFields(o, Op::kHeader, r, headerFields<Writer, const Header>);
}

void appendRecord(std::string& o, const Footer& r) {
  appendFields(o, Op::kFooter, r, footerFields<Writer, const Footer>);
}

void appendRecord(std::string& o, const Schema& r) {
  appendFields(o, Op::kSchema, r, schemaFields<Writer, const Schema>);
}

void appendRecord(std::string& o, const Channel& r) {
  const size_t at = beginRecord(o, Op::kChannel);
  Writer w{o};
  channelFields(w, r);
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
  appendFields(o, Op::kChunkIndex, r, chunkIndexFields<Writer, const ChunkIndex>);
}

void appendRecord(std::string& o, const Statistics& r) {
  appendFields(o, Op::kStatistics, r, statisticsFields<Writer, const Statistics>);
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
  Writer w{o};
  messageFields(w, h);
  o.append(static_cast<const char*>(data), size);
  endRecord(o, at);
}

void appendChunk(std::string& o, ChunkHeader h, const std::string& records) {
  const size_t at = beginRecord(o, Op::kChunk);
  Writer w{o};
  chunkFields(w, h);
  u64(o, records.size());
  o += records;
  endRecord(o, at);
}

void parseRecord(const uint8_t* p, size_t n, Header& r) {
  parseFields(p, n, "header", r, headerFields<Reader, Header>);
}

void parseRecord(const uint8_t* p, size_t n, Footer& r) {
  parseFields(p, n, "footer", r, footerFields<Reader, Footer>);
}

void parseRecord(const uint8_t* p, size_t n, Schema& r) {
  parseFields(p, n, "schema", r, schemaFields<Reader, Schema>);
}

void parseRecord(const uint8_t* p, size_t n, Channel& r) {
  Cursor c(p, n, "channel");
  Reader in{c};
  channelFields(in, r);
  const size_t at = c.at();
  const auto len = c.uint<uint32_t>("metadata");
  if (len > c.left()) throw RecordError(at, "channel metadata exceeds the record");
  Cursor m(p + c.at(), len, "channel");
  r.metadata.clear();
  while (m.left() > 0) {
    std::string key = m.str("metadata key");
    r.metadata.emplace_back(std::move(key), m.str("metadata value"));
  }
}

void parseRecord(const uint8_t* p, size_t n, ChunkIndex& r) {
  parseFields(p, n, "chunk index", r, chunkIndexFields<Reader, ChunkIndex>);
}

void parseRecord(const uint8_t* p, size_t n, Statistics& r) {
  parseFields(p, n, "statistics", r, statisticsFields<Reader, Statistics>);
}

size_t parseMessage(const uint8_t* p, size_t n, MessageHeader& r) {
  Cursor c(p, n, "message");
  Reader in{c};
  messageFields(in, r);
  return c.at();
}

size_t parseChunk(const uint8_t* p, size_t n, ChunkHeader& r) {
  Cursor c(p, n, "chunk");
  Reader in{c};
  chunkFields(in, r);
  const size_t at = c.at();
  r.records_size = c.uint<uint64_t>("records_size");
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
