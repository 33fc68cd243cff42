// The indexed MCAP writer.
#include "plugslam/mcap/writer.h"

#include <algorithm>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

Writer::Writer(const std::string& path, WriterOptions options)
    : path_(path), options_(std::move(options)) {
  if (!options_.compression.empty() && !options_.compress)
    throw InputError("MCAP writer: compression '" + options_.compression +
                     "' needs a compress function");
  file_.open(path, std::ios::binary | std::ios::trunc);
  if (!file_) throw InputError("cannot write the recording '" + path + "'");
  std::string head(kMagic, sizeof(kMagic));
  appendRecord(head, Header{options_.profile, options_.library});
  put(head);
}

Writer::~Writer() {
  try {
    close();
  } catch (...) {
    // The destructor must not throw; close() reports the same failure to a caller who asks.
  }
}

void Writer::put(const std::string& bytes) {
  file_.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!file_) throw Error("write to the recording '" + path_ + "' failed (disk full?)");
  data_crc_ = crc32(bytes.data(), bytes.size(), data_crc_);
  offset_ += bytes.size();
}

uint16_t Writer::addSchema(const std::string& name, const std::string& encoding,
                           const std::string& data) {
  if (schemas_.size() >= 0xFFFE) throw InputError("MCAP writer: too many schemas");
  Schema s{static_cast<uint16_t>(schemas_.size() + 1), name, encoding, data};
  appendRecord(chunk_, s);  // in the data section too, before any channel that uses it
  schemas_.push_back(std::move(s));
  return schemas_.back().id;
}

uint16_t Writer::addChannel(uint16_t schema_id, const std::string& topic,
                            const std::string& message_encoding,
                            std::vector<std::pair<std::string, std::string>> metadata) {
  if (channels_.size() >= 0xFFFF) throw InputError("MCAP writer: too many channels");
  if (schema_id > schemas_.size())
    throw InputError("MCAP writer: channel '" + topic + "' names an unknown schema");
  Channel c{static_cast<uint16_t>(channels_.size()), schema_id, topic, message_encoding,
            std::move(metadata)};
  appendRecord(chunk_, c);
  channels_.push_back(std::move(c));
  return channels_.back().id;
}

void Writer::write(uint16_t channel, uint64_t log_time, uint64_t publish_time, const void* data,
                   size_t size) {
  if (closed_) throw InputError("MCAP writer: '" + path_ + "' is closed");
  if (channel >= channels_.size()) throw InputError("MCAP writer: unknown channel");
  MessageIndex& index = chunk_index_[channel];
  index.channel_id = channel;
  index.records.emplace_back(log_time, chunk_.size());
  appendMessage(chunk_, MessageHeader{channel, sequences_[channel]++, log_time, publish_time},
                data, size);
  if (!chunk_has_messages_) {
    chunk_start_ = chunk_end_ = log_time;
    chunk_has_messages_ = true;
  }
  chunk_start_ = std::min(chunk_start_, log_time);
  chunk_end_ = std::max(chunk_end_, log_time);
  if (stats_.message_count == 0) stats_.message_start_time = stats_.message_end_time = log_time;
  stats_.message_start_time = std::min(stats_.message_start_time, log_time);
  stats_.message_end_time = std::max(stats_.message_end_time, log_time);
  ++stats_.message_count;
  ++channel_counts_[channel];
  if (chunk_.size() >= options_.chunk_size) flushChunk();
}

void Writer::flushChunk() {
  if (chunk_.empty()) return;
  ChunkHeader header;
  header.message_start_time = chunk_has_messages_ ? chunk_start_ : 0;
  header.message_end_time = chunk_has_messages_ ? chunk_end_ : 0;
  header.uncompressed_size = chunk_.size();
  header.uncompressed_crc = crc32(chunk_.data(), chunk_.size());
  header.compression = options_.compression;
  const std::string stored = options_.compress ? options_.compress(chunk_) : std::string();
  const std::string& records = options_.compress ? stored : chunk_;

  ChunkIndex ci;
  ci.message_start_time = header.message_start_time;
  ci.message_end_time = header.message_end_time;
  ci.chunk_start_offset = offset_;
  ci.compression = header.compression;
  ci.compressed_size = records.size();
  ci.uncompressed_size = chunk_.size();
  std::string out;
  appendChunk(out, header, records);
  ci.chunk_length = out.size();
  // The message indexes follow the chunk, one per channel with messages in it.
  for (const auto& [channel, index] : chunk_index_) {
    ci.message_index_offsets.emplace_back(channel, offset_ + out.size());
    const size_t before = out.size();
    appendRecord(out, index);
    ci.message_index_length += out.size() - before;
  }
  put(out);
  chunk_indexes_.push_back(std::move(ci));
  ++stats_.chunk_count;
  chunk_.clear();
  chunk_index_.clear();
  chunk_has_messages_ = false;
}

void Writer::close() {
  if (closed_) return;
  closed_ = true;
  flushChunk();
  std::string end;
  appendDataEnd(end, data_crc_);
  put(end);

  // The summary, grouped by opcode, each group located by a Summary Offset record.
  const uint64_t summary_start = offset_;
  std::string summary;
  std::vector<SummaryOffset> groups;
  auto group = [&](Op op, auto&& emit) {
    const size_t before = summary.size();
    emit();
    if (summary.size() > before)
      groups.push_back(SummaryOffset{op, summary_start + before, summary.size() - before});
  };
  group(Op::kSchema, [&] {
    for (const auto& s : schemas_) appendRecord(summary, s);
  });
  group(Op::kChannel, [&] {
    for (const auto& c : channels_) appendRecord(summary, c);
  });
  group(Op::kChunkIndex, [&] {
    for (const auto& ci : chunk_indexes_) appendRecord(summary, ci);
  });
  stats_.schema_count = static_cast<uint16_t>(schemas_.size());
  stats_.channel_count = static_cast<uint32_t>(channels_.size());
  stats_.channel_message_counts.assign(channel_counts_.begin(), channel_counts_.end());
  group(Op::kStatistics, [&] { appendRecord(summary, stats_); });
  const uint64_t summary_offset_start = summary_start + summary.size();
  for (const auto& g : groups) appendRecord(summary, g);

  Footer footer{summary_start, summary_offset_start, 0};
  std::string tail;
  appendRecord(tail, footer);
  // The summary CRC covers the summary and the footer up to its summary_crc field.
  const size_t footer_prefix = tail.size() - 4;
  uint32_t crc = crc32(summary.data(), summary.size());
  crc = crc32(tail.data(), footer_prefix, crc);
  tail.clear();
  footer.summary_crc = crc;
  appendRecord(tail, footer);
  tail.append(kMagic, sizeof(kMagic));
  put(summary);
  put(tail);
  file_.flush();
  if (!file_) throw Error("write to the recording '" + path_ + "' failed (disk full?)");
  file_.close();
}

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
