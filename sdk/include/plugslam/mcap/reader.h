#pragma once
// An MCAP reader on the record layer of records.h (the one the Writer uses). With a summary it
// knows every schema and channel up front and visits the chunks through their indexes, skipping
// the chunks that hold none of the wanted topics; without one (a recording cut short, a writer
// that writes no summary) it scans the data section record by record, and a file cut mid-record
// keeps every complete record before the cut (a warning names the offset). Chunks may be
// uncompressed, lz4 (frame format) or zstd; their CRCs and the summary's are checked, and a scan
// checks Data End's data section CRC (0 = not computed by the writer). Every
// malformed input is a ParseError naming the file and the byte offset.
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "plugslam/mcap/records.h"

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

/// How a Reader reads.
struct ReaderOptions {
  std::set<std::string> topics;  ///< topics to return; empty = every topic
  bool use_summary = true;       ///< false: always a linear scan (tests, damaged summaries)
  bool check_crc = true;         ///< check the chunk, summary and (scans) data section CRCs
                                 ///< when the file has them
  /// Upper bound of one record and of a decompressed chunk [bytes] (a corrupt length would
  /// otherwise allocate the machine's memory).
  uint64_t max_record_bytes = uint64_t{1} << 32;
};

/// One message as read.
struct ReadMessage {
  const Channel* channel = nullptr;  ///< owned by the reader, valid while it lives
  const Schema* schema = nullptr;    ///< its schema; nullptr when the channel has none
  MessageHeader header;              ///< channel, sequence and times (ns)
  std::string data;                  ///< the serialized message
  uint64_t offset = 0;               ///< file offset of its Message record or of its chunk
};

/// Counters of one read.
struct ReaderStats {
  bool indexed = false;          ///< the chunk indexes of the summary were used
  uint64_t chunks = 0;           ///< chunks decompressed
  uint64_t chunks_skipped = 0;   ///< chunks the index showed to hold no wanted topic
  uint64_t messages = 0;         ///< messages returned
  uint64_t filtered = 0;         ///< messages of other topics, not returned
  uint64_t truncated_at = 0;     ///< offset of the record cut short; 0 = the file is whole
  uint64_t bytes = 0;            ///< file size
  std::map<std::string, uint64_t> compression;  ///< chunks per compression ("" = none)
};

/// Reads one MCAP file; next() returns messages chunk by chunk (chunks in time order when
/// indexed, file order when scanned), each chunk's messages in log-time order.
class Reader {
 public:
  /// Opens `path`, checks the magic and reads the summary; InputError if it cannot be read,
  /// ParseError if it is not MCAP.
  explicit Reader(const std::string& path, ReaderOptions options = {});
  /// Reads a file held in memory; `name` stands for the path in messages. For tests and fuzzers.
  static std::unique_ptr<Reader> fromBytes(std::string name, std::string bytes,
                                           ReaderOptions options = {});
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  /// The next message of a wanted topic; false at the end. ParseError (file, byte offset) on a
  /// corrupt chunk or record.
  bool next(ReadMessage& message);

  /// The header record.
  const Header& header() const;
  /// Channels by id: all of them when the file has a summary, else those seen so far.
  const std::map<uint16_t, Channel>& channels() const;
  /// Schemas by id, as channels().
  const std::map<uint16_t, Schema>& schemas() const;
  /// The summary's statistics, when the file has them.
  const std::optional<Statistics>& statistics() const;
  /// Counters so far.
  const ReaderStats& stats() const;
  /// The path being read.
  const std::string& path() const;

 private:
  struct Impl;
  Reader(std::string name, std::string bytes, ReaderOptions options, bool in_memory);
  std::unique_ptr<Impl> impl_;
};

/// Decompresses MCAP chunk records ("" = stored, "lz4" = lz4 frame, "zstd") to exactly
/// `uncompressed_size` bytes; throws RecordError(0, why) when they do not decompress to it.
std::string decompress(const std::string& compression, const uint8_t* data, size_t size,
                       uint64_t uncompressed_size);

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
