#pragma once
// The MCAP record layer (https://mcap.dev/spec, major version 0): the records, their byte layout
// and the CRC. One implementation of the format, in the SDK so that the runtime (recordings) and
// plugins (reading MCAP input) share it. Integers are little-endian; strings and maps carry a
// uint32 byte length.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

/// The 8 bytes that open and close every MCAP file.
constexpr char kMagic[8] = {'\x89', 'M', 'C', 'A', 'P', '0', '\r', '\n'};

/// Record opcodes.
enum class Op : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// CRC-32 (the ISO-HDLC polynomial MCAP and zlib use) of `size` bytes, continuing `crc`.
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);

/// First record of a file.
struct Header {
  std::string profile;  ///< "" or a well-known profile ("ros2")
  std::string library;  ///< the writer's name and version
};
/// Last record of a file: where the summary is.
struct Footer {
  uint64_t summary_start = 0;         ///< offset of the summary section, 0 without one
  uint64_t summary_offset_start = 0;  ///< offset of the summary offset section, 0 without one
  uint32_t summary_crc = 0;           ///< CRC of the summary through summary_offset_start; 0: none
};
/// A message schema.
struct Schema {
  uint16_t id = 0;       ///< > 0, unique in the file
  std::string name;      ///< "foxglove.PointCloud"
  std::string encoding;  ///< "jsonschema", "ros2msg", ...; "" = no schema
  std::string data;      ///< the schema text or bytes
};
/// A stream of messages on one topic.
struct Channel {
  uint16_t id = 0;                ///< unique in the file
  uint16_t schema_id = 0;         ///< 0: no schema
  std::string topic;              ///< "/scan"
  std::string message_encoding;   ///< "json", "cdr", ...
  std::vector<std::pair<std::string, std::string>> metadata;  ///< key -> value
};
/// One timestamped message (its data is kept apart: Message records are written and read in
/// place).
struct MessageHeader {
  uint16_t channel_id = 0;    ///< its channel
  uint32_t sequence = 0;      ///< publisher's counter
  uint64_t log_time = 0;      ///< ns when recorded
  uint64_t publish_time = 0;  ///< ns when published
};
/// The messages of one channel inside a chunk: (log_time, offset in the uncompressed records).
struct MessageIndex {
  uint16_t channel_id = 0;                              ///< the channel
  std::vector<std::pair<uint64_t, uint64_t>> records;  ///< (log_time, offset), in file order
};
/// A chunk's header fields (its records follow, maybe compressed).
struct ChunkHeader {
  uint64_t message_start_time = 0;  ///< earliest log_time in it
  uint64_t message_end_time = 0;    ///< latest log_time in it
  uint64_t uncompressed_size = 0;   ///< size of the records, uncompressed
  uint32_t uncompressed_crc = 0;    ///< CRC of the uncompressed records; 0: none
  std::string compression;          ///< "", "zstd" or "lz4"
  uint64_t records_size = 0;        ///< size of the records as stored
};
/// Where a chunk and its message indexes are.
struct ChunkIndex {
  uint64_t message_start_time = 0;  ///< as in the chunk
  uint64_t message_end_time = 0;    ///< as in the chunk
  uint64_t chunk_start_offset = 0;  ///< file offset of the chunk record
  uint64_t chunk_length = 0;        ///< its length, opcode and length prefix included
  std::vector<std::pair<uint16_t, uint64_t>> message_index_offsets;  ///< channel -> offset
  uint64_t message_index_length = 0;  ///< bytes of message index records after the chunk
  std::string compression;            ///< as in the chunk
  uint64_t compressed_size = 0;       ///< stored size of the chunk's records
  uint64_t uncompressed_size = 0;     ///< their uncompressed size
};
/// Counts over the whole file.
struct Statistics {
  uint64_t message_count = 0;     ///< Message records
  uint16_t schema_count = 0;      ///< distinct schema ids
  uint32_t channel_count = 0;     ///< distinct channel ids
  uint32_t attachment_count = 0;  ///< Attachment records
  uint32_t metadata_count = 0;    ///< Metadata records
  uint32_t chunk_count = 0;       ///< Chunk records
  uint64_t message_start_time = 0;  ///< earliest log_time
  uint64_t message_end_time = 0;    ///< latest log_time
  std::vector<std::pair<uint16_t, uint64_t>> channel_message_counts;  ///< channel -> messages
};
/// Where one group of same-opcode records of the summary is.
struct SummaryOffset {
  Op group_opcode = Op::kSchema;  ///< the group's opcode
  uint64_t group_start = 0;       ///< file offset of its first record
  uint64_t group_length = 0;      ///< its total length
};

/// Appends whole records (opcode, uint64 length, content) to `out`.
void appendRecord(std::string& out, const Header& r);
void appendRecord(std::string& out, const Footer& r);
void appendRecord(std::string& out, const Schema& r);
void appendRecord(std::string& out, const Channel& r);
void appendRecord(std::string& out, const MessageIndex& r);
void appendRecord(std::string& out, const ChunkIndex& r);
void appendRecord(std::string& out, const Statistics& r);
void appendRecord(std::string& out, const SummaryOffset& r);
/// Appends a Data End record carrying the CRC of every byte before it.
void appendDataEnd(std::string& out, uint32_t data_section_crc);
/// Appends a Message record.
void appendMessage(std::string& out, const MessageHeader& header, const void* data, size_t size);
/// Appends a Chunk record around `records` (already compressed as `header.compression` says;
/// header.records_size is set from `records`).
void appendChunk(std::string& out, ChunkHeader header, const std::string& records);

/// A record's content ended before its fields did; `at` is the byte offset into the content.
class RecordError : public std::runtime_error {
 public:
  RecordError(uint64_t at, const std::string& what) : std::runtime_error(what), at(at) {}
  uint64_t at;  ///< offset into the record's content where the field starts
};

/// Parse a record's content (the bytes after its opcode and uint64 length); RecordError when
/// it is shorter than its fields.
void parseRecord(const uint8_t* content, size_t size, Header& out);
void parseRecord(const uint8_t* content, size_t size, Footer& out);
void parseRecord(const uint8_t* content, size_t size, Schema& out);
void parseRecord(const uint8_t* content, size_t size, Channel& out);
void parseRecord(const uint8_t* content, size_t size, ChunkIndex& out);
void parseRecord(const uint8_t* content, size_t size, Statistics& out);
/// Parses a Message record's header; returns the offset of its data in the content.
size_t parseMessage(const uint8_t* content, size_t size, MessageHeader& out);
/// Parses a Chunk record's header fields; returns the offset of its records in the content.
size_t parseChunk(const uint8_t* content, size_t size, ChunkHeader& out);

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
