#pragma once
// An indexed MCAP writer: messages go into chunks, each followed by its message indexes; closing
// writes the summary (schemas, channels, chunk indexes, statistics) and the summary offsets, so
// readers such as Foxglove and Lichtblick seek without reading the whole file. The file is written
// in place as it grows, so a killed recording keeps every chunk finished before (stream readers
// recover it); only close() makes it indexed.
#include <cstdint>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "plugslam/mcap/records.h"

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

/// How a Writer lays out its file.
struct WriterOptions {
  std::string profile;                 ///< Header profile ("" for none)
  std::string library = "plugslam";    ///< Header library
  size_t chunk_size = 1 << 20;         ///< a chunk is closed once its records reach this [bytes]
  std::string compression;             ///< chunk compression name ("" = none)
  /// Compresses a chunk's records (required when `compression` is set).
  std::function<std::string(const std::string& records)> compress;
};

/// Writes one MCAP file. Not thread-safe. Throws plugslam::Error when the file cannot be written.
class Writer {
 public:
  /// Creates (or truncates) `path` and writes the magic and header.
  explicit Writer(const std::string& path, WriterOptions options = {});
  /// Closes the file if close() was not called (errors are swallowed: call close() to see them).
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  /// Adds a schema; returns its id (> 0).
  uint16_t addSchema(const std::string& name, const std::string& encoding, const std::string& data);
  /// Adds a channel of schema `schema_id` (0: none); returns its id.
  uint16_t addChannel(uint16_t schema_id, const std::string& topic,
                      const std::string& message_encoding,
                      std::vector<std::pair<std::string, std::string>> metadata = {});
  /// Writes one message on `channel`; times in nanoseconds.
  void write(uint16_t channel, uint64_t log_time, uint64_t publish_time, const void* data,
             size_t size);
  /// Finishes the file: the last chunk, Data End, the summary, the footer and the magic.
  void close();
  /// Bytes written to the file so far.
  uint64_t bytesWritten() const { return offset_; }
  /// Messages written so far.
  uint64_t messages() const { return stats_.message_count; }

 private:
  void put(const std::string& bytes);  // to the file, counting offset and CRC
  void flushChunk();
  std::string path_;
  WriterOptions options_;
  std::ofstream file_;
  uint64_t offset_ = 0;
  uint32_t data_crc_ = 0;
  bool closed_ = false;
  std::vector<Schema> schemas_;
  std::vector<Channel> channels_;
  std::vector<ChunkIndex> chunk_indexes_;
  Statistics stats_;
  std::map<uint16_t, uint64_t> channel_counts_;
  std::map<uint16_t, uint32_t> sequences_;
  // The open chunk: its uncompressed records, time span and per-channel message index.
  std::string chunk_;
  uint64_t chunk_start_ = 0, chunk_end_ = 0;
  bool chunk_has_messages_ = false;
  std::map<uint16_t, MessageIndex> chunk_index_;
};

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
