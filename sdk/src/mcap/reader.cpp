// The MCAP reader: summary and chunk indexes when present, a linear scan when not.
#include "plugslam/mcap/reader.h"

#include <lz4frame.h>
#include <spdlog/spdlog.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <deque>
#include <fstream>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {
namespace mcap {

namespace {

// Opcode and uint64 length in front of every record.
constexpr uint64_t kPrefix = 9;
// Footer record: prefix + summary_start + summary_offset_start + summary_crc.
constexpr uint64_t kFooterRecord = kPrefix + 8 + 8 + 4;

uint64_t le64(const char* p) {
  uint64_t v = 0;
  for (int k = 0; k < 8; ++k) v |= uint64_t{static_cast<uint8_t>(p[k])} << (8 * k);
  return v;
}

const uint8_t* bytesOf(const std::string& s) { return reinterpret_cast<const uint8_t*>(s.data()); }

std::string lz4Decompress(const uint8_t* data, size_t size, uint64_t expected) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) {
    throw RecordError(0, "cannot initialise lz4");
  }
  struct Free {
    LZ4F_dctx* c;
    ~Free() { LZ4F_freeDecompressionContext(c); }
  } guard{ctx};
  std::string out(expected, '\0');
  size_t produced = 0, consumed = 0;
  for (;;) {
    size_t dst = out.size() - produced;
    size_t src = size - consumed;
    const size_t hint = LZ4F_decompress(ctx, out.data() + produced, &dst, data + consumed, &src,
                                        nullptr);
    if (LZ4F_isError(hint)) {
      throw RecordError(consumed, std::string("lz4 data is corrupt: ") + LZ4F_getErrorName(hint));
    }
    produced += dst;
    consumed += src;
    if (hint == 0) break;  // the frame is complete
    if (consumed == size) throw RecordError(consumed, "lz4 data is truncated");
    if (dst == 0 && src == 0) {
      throw RecordError(consumed, "lz4 data holds more than the declared " +
                                      std::to_string(expected) + " bytes");
    }
  }
  if (produced != expected) {
    throw RecordError(consumed, "lz4 data decompressed to " + std::to_string(produced) +
                                    " bytes; the chunk says " + std::to_string(expected));
  }
  return out;
}

std::string zstdDecompress(const uint8_t* data, size_t size, uint64_t expected) {
  std::string out(expected, '\0');
  const size_t n = ZSTD_decompress(out.data(), out.size(), data, size);
  if (ZSTD_isError(n)) {
    throw RecordError(0, std::string("zstd data does not decompress: ") + ZSTD_getErrorName(n));
  }
  if (n != expected) {
    throw RecordError(0, "zstd data decompressed to " + std::to_string(n) +
                             " bytes; the chunk says " + std::to_string(expected));
  }
  return out;
}

}  // namespace

std::string decompress(const std::string& compression, const uint8_t* data, size_t size,
                       uint64_t uncompressed_size) {
  if (compression.empty()) {
    if (size != uncompressed_size) {
      throw RecordError(0, "stored chunk of " + std::to_string(size) + " bytes; it says " +
                               std::to_string(uncompressed_size));
    }
    return std::string(reinterpret_cast<const char*>(data), size);
  }
  if (compression == "lz4") return lz4Decompress(data, size, uncompressed_size);
  if (compression == "zstd") return zstdDecompress(data, size, uncompressed_size);
  throw RecordError(0, "unknown chunk compression '" + compression +
                           "' (known: none, lz4, zstd)");
}

struct Reader::Impl {
  std::string path;
  ReaderOptions options;
  bool in_memory = false;
  std::string bytes;  // the file when in memory
  std::ifstream file;
  uint64_t size = 0;

  Header header;
  std::map<uint16_t, Channel> channels;
  std::map<uint16_t, Schema> schemas;
  std::optional<Statistics> statistics;
  ReaderStats stats;

  bool indexed = false;
  std::vector<ChunkIndex> chunks;  // in reading order
  size_t next_chunk = 0;
  uint64_t position = 0;  // linear scan: the next top-level record
  // Linear scan: the CRC of the bytes [0, data_crc_to) read so far, for Data End's check.
  uint32_t data_crc = 0;
  uint64_t data_crc_to = 0;
  bool done = false;
  std::deque<ReadMessage> queue;

  [[noreturn]] void fail(uint64_t offset, const std::string& message) const {
    throw ParseError(path, 0, "byte offset " + std::to_string(offset) + ": " + message);
  }

  std::string read(uint64_t offset, uint64_t n) {
    if (offset > size || n > size - offset) {
      fail(offset, "needs " + std::to_string(n) + " bytes, the file has " +
                       std::to_string(offset > size ? 0 : size - offset) + " left");
    }
    if (in_memory) return bytes.substr(offset, n);
    std::string out(n, '\0');
    file.clear();
    file.seekg(static_cast<std::streamoff>(offset));
    file.read(out.data(), static_cast<std::streamsize>(n));
    if (!file) fail(offset, "read error");
    return out;
  }

  template <typename Record>
  void parse(const std::string& content, uint64_t offset, Record& r, const char* what) const {
    try {
      parseRecord(bytesOf(content), content.size(), r);
    } catch (const RecordError& e) {
      fail(offset + e.at, std::string(what) + ": " + e.what());
    }
  }

  bool wanted(const Channel& c) const {
    return options.topics.empty() || options.topics.count(c.topic) > 0;
  }

  void open() {
    const std::string magic = read(0, std::min<uint64_t>(size, sizeof(kMagic)));
    if (magic.size() < sizeof(kMagic) || std::memcmp(magic.data(), kMagic, sizeof(kMagic)) != 0) {
      fail(0, "not an MCAP file (no MCAP magic)");
    }
    stats.bytes = size;
    position = sizeof(kMagic);
    data_crc = crc32(kMagic, sizeof(kMagic));
    data_crc_to = position;
    if (size - position < kPrefix || read(position, 1)[0] != static_cast<char>(Op::kHeader)) {
      fail(position, "expected the header record after the magic");
    }
    const uint64_t header_len = le64(read(position + 1, 8).data());
    if (header_len > size - position - kPrefix) fail(position, "header record cut short");
    parse(read(position + kPrefix, header_len), position + kPrefix, header, "header");
    if (options.use_summary) readSummary();
    stats.indexed = indexed;
  }

  // Reads the footer and the summary; leaves indexed false when there are none to use.
  void readSummary() {
    if (size < 2 * sizeof(kMagic) + kFooterRecord) return;
    const uint64_t footer_at = size - sizeof(kMagic) - kFooterRecord;
    const std::string tail = read(footer_at, kFooterRecord + sizeof(kMagic));
    if (std::memcmp(tail.data() + kFooterRecord, kMagic, sizeof(kMagic)) != 0 ||
        tail[0] != static_cast<char>(Op::kFooter) || le64(tail.data() + 1) != kFooterRecord - kPrefix) {
      spdlog::warn("MCAP '{}': no footer at the end (a recording cut short?); scanning it", path);
      return;
    }
    Footer footer;
    parse(tail.substr(kPrefix, kFooterRecord - kPrefix), footer_at + kPrefix, footer, "footer");
    if (footer.summary_start == 0) return;  // a writer without summary: scan
    if (footer.summary_start < sizeof(kMagic) || footer.summary_start > footer_at) {
      fail(footer_at, "footer's summary_start " + std::to_string(footer.summary_start) +
                          " is outside the file");
    }
    const uint64_t summary_end =
        footer.summary_offset_start != 0 ? footer.summary_offset_start : footer_at;
    if (summary_end < footer.summary_start || summary_end > footer_at) {
      fail(footer_at, "footer's summary_offset_start is outside the summary");
    }
    if (options.check_crc && footer.summary_crc != 0) {
      // Summary through the footer's summary_offset_start field.
      const std::string covered =
          read(footer.summary_start, footer_at + kPrefix + 16 - footer.summary_start);
      const uint32_t crc = crc32(covered.data(), covered.size());
      if (crc != footer.summary_crc) {
        fail(footer.summary_start, "summary CRC mismatch (stored " +
                                       std::to_string(footer.summary_crc) + ", computed " +
                                       std::to_string(crc) + ")");
      }
    }
    const std::string summary = read(footer.summary_start, summary_end - footer.summary_start);
    uint64_t i = 0;
    while (i < summary.size()) {
      const uint64_t at = footer.summary_start + i;
      if (summary.size() - i < kPrefix) fail(at, "summary record cut short");
      const auto op = static_cast<Op>(summary[i]);
      const uint64_t len = le64(summary.data() + i + 1);
      if (len > summary.size() - i - kPrefix) {
        fail(at, "summary record of " + std::to_string(len) + " bytes exceeds the summary");
      }
      const std::string content = summary.substr(i + kPrefix, len);
      if (op == Op::kSchema) {
        Schema s;
        parse(content, at + kPrefix, s, "schema");
        schemas[s.id] = std::move(s);
      } else if (op == Op::kChannel) {
        Channel c;
        parse(content, at + kPrefix, c, "channel");
        channels[c.id] = std::move(c);
      } else if (op == Op::kChunkIndex) {
        ChunkIndex c;
        parse(content, at + kPrefix, c, "chunk index");
        if (c.chunk_start_offset > size || c.chunk_length > size - c.chunk_start_offset) {
          fail(at, "chunk index points at bytes " + std::to_string(c.chunk_start_offset) + "+" +
                       std::to_string(c.chunk_length) + " beyond the file");
        }
        chunks.push_back(std::move(c));
      } else if (op == Op::kStatistics) {
        Statistics s;
        parse(content, at + kPrefix, s, "statistics");
        statistics = std::move(s);
      }
      i += kPrefix + len;
    }
    std::stable_sort(chunks.begin(), chunks.end(), [](const ChunkIndex& a, const ChunkIndex& b) {
      return a.message_start_time != b.message_start_time
                 ? a.message_start_time < b.message_start_time
                 : a.chunk_start_offset < b.chunk_start_offset;
    });
    // A summary without chunk indexes (messages outside chunks) is scanned, unless it says
    // the file holds no message at all.
    indexed = !chunks.empty() || (statistics && statistics->message_count == 0);
    if (indexed) done = chunks.empty();
  }

  void addMessage(const uint8_t* p, uint64_t n, uint64_t offset, uint64_t report_at) {
    MessageHeader h;
    size_t data_at = 0;
    try {
      data_at = parseMessage(p, n, h);
    } catch (const RecordError& e) {
      fail(report_at, std::string("message: ") + e.what());
    }
    const auto c = channels.find(h.channel_id);
    if (c == channels.end()) {
      fail(report_at, "message on channel " + std::to_string(h.channel_id) +
                          ", which no channel record defines before it");
    }
    if (!wanted(c->second)) {
      ++stats.filtered;
      return;
    }
    ReadMessage m;
    m.channel = &c->second;
    const auto s = schemas.find(c->second.schema_id);
    m.schema = c->second.schema_id != 0 && s != schemas.end() ? &s->second : nullptr;
    m.header = h;
    m.data.assign(reinterpret_cast<const char*>(p) + data_at, n - data_at);
    m.offset = offset;
    queue.push_back(std::move(m));
  }

  void addChannel(const uint8_t* p, uint64_t n, uint64_t report_at) {
    Channel c;
    try {
      parseRecord(p, n, c);
    } catch (const RecordError& e) {
      fail(report_at, std::string("channel: ") + e.what());
    }
    channels[c.id] = std::move(c);
  }

  void addSchema(const uint8_t* p, uint64_t n, uint64_t report_at) {
    Schema s;
    try {
      parseRecord(p, n, s);
    } catch (const RecordError& e) {
      fail(report_at, std::string("schema: ") + e.what());
    }
    schemas[s.id] = std::move(s);
  }

  // Decompresses one chunk (its content starts at file offset `content_at`) and queues its
  // messages in log-time order.
  void loadChunk(const std::string& content, uint64_t chunk_at) {
    const uint64_t content_at = chunk_at + kPrefix;
    ChunkHeader h;
    size_t records_at = 0;
    try {
      records_at = parseChunk(bytesOf(content), content.size(), h);
    } catch (const RecordError& e) {
      fail(content_at + e.at, std::string("chunk: ") + e.what());
    }
    if (h.uncompressed_size > options.max_record_bytes) {
      fail(chunk_at, "chunk claims " + std::to_string(h.uncompressed_size) +
                         " uncompressed bytes, more than the limit of " +
                         std::to_string(options.max_record_bytes));
    }
    std::string records;
    try {
      records = decompress(h.compression, bytesOf(content) + records_at, h.records_size,
                           h.uncompressed_size);
    } catch (const RecordError& e) {
      fail(chunk_at, "chunk (" + (h.compression.empty() ? std::string("uncompressed") : h.compression) +
                         ") does not decompress: " + e.what());
    }
    ++stats.chunks;
    ++stats.compression[h.compression];
    if (options.check_crc && h.uncompressed_crc != 0) {
      const uint32_t crc = crc32(records.data(), records.size());
      if (crc != h.uncompressed_crc) {
        fail(chunk_at, "chunk CRC mismatch (stored " + std::to_string(h.uncompressed_crc) +
                           ", computed " + std::to_string(crc) + ")");
      }
    }
    const size_t first = queue.size();
    const uint8_t* p = bytesOf(records);
    uint64_t i = 0;
    while (i < records.size()) {
      auto inner = [&](const std::string& what) {
        fail(chunk_at, "record at byte " + std::to_string(i) + " of the chunk's " +
                           std::to_string(records.size()) + " uncompressed bytes: " + what);
      };
      if (records.size() - i < kPrefix) inner("cut short");
      const auto op = static_cast<Op>(p[i]);
      const uint64_t len = le64(records.data() + i + 1);
      if (len > records.size() - i - kPrefix) {
        inner("its " + std::to_string(len) + " bytes exceed the chunk");
      }
      const uint8_t* c = p + i + kPrefix;
      if (op == Op::kMessage) {
        addMessage(c, len, chunk_at, chunk_at);
      } else if (op == Op::kChannel) {
        addChannel(c, len, chunk_at);
      } else if (op == Op::kSchema) {
        addSchema(c, len, chunk_at);
      }
      i += kPrefix + len;
    }
    std::stable_sort(queue.begin() + static_cast<std::ptrdiff_t>(first), queue.end(),
                     [](const ReadMessage& a, const ReadMessage& b) {
                       return a.header.log_time < b.header.log_time;
                     });
  }

  void truncated(uint64_t at, const std::string& why) {
    stats.truncated_at = at;
    done = true;
    spdlog::warn("MCAP '{}': cut short at byte offset {} ({}); read the {} message(s) before it",
                 path, at, why, stats.messages + queue.size());
  }

  // Linear scan: one top-level record.
  void scanOne() {
    if (position >= size) {
      done = true;
      return;
    }
    if (size - position < kPrefix) return truncated(position, "record prefix incomplete");
    const std::string prefix = read(position, kPrefix);
    const auto op = static_cast<Op>(prefix[0]);
    const uint64_t len = le64(prefix.data() + 1);
    if (len > size - position - kPrefix) {
      return truncated(position, "record of " + std::to_string(len) + " bytes, " +
                                     std::to_string(size - position - kPrefix) + " left");
    }
    if (len > options.max_record_bytes) {
      fail(position, "record of " + std::to_string(len) + " bytes exceeds the limit");
    }
    const uint64_t at = position;
    position += kPrefix + len;
    const std::string c = read(at + kPrefix, len);
    if (op == Op::kDataEnd) {
      // data_section_crc: every byte from the magic to this record; 0 = not computed.
      if (len < 4) fail(at, "data end record of " + std::to_string(len) + " bytes (expected 4)");
      const uint32_t stored = static_cast<uint32_t>(static_cast<uint8_t>(c[0])) |
                              static_cast<uint32_t>(static_cast<uint8_t>(c[1])) << 8 |
                              static_cast<uint32_t>(static_cast<uint8_t>(c[2])) << 16 |
                              static_cast<uint32_t>(static_cast<uint8_t>(c[3])) << 24;
      if (options.check_crc && stored != 0 && data_crc_to == at && data_crc != stored) {
        fail(at, "data section CRC mismatch (stored " + std::to_string(stored) + ", computed " +
                     std::to_string(data_crc) + "): bytes before it are damaged");
      }
      done = true;
      return;
    }
    if (data_crc_to == at) {
      data_crc = crc32(prefix.data(), prefix.size(), data_crc);
      data_crc = crc32(c.data(), c.size(), data_crc);
      data_crc_to = position;
    }
    switch (op) {
      case Op::kHeader: parse(c, at + kPrefix, header, "header"); break;
      case Op::kSchema: addSchema(bytesOf(c), len, at); break;
      case Op::kChannel: addChannel(bytesOf(c), len, at); break;
      case Op::kMessage: addMessage(bytesOf(c), len, at, at); break;
      case Op::kChunk: loadChunk(c, at); break;
      case Op::kFooter: done = true; break;
      default: break;  // indexes, attachments, metadata: not needed to read messages
    }
  }

  // Indexed: the next chunk holding a wanted channel.
  void chunkOne() {
    if (next_chunk >= chunks.size()) {
      done = true;
      return;
    }
    const ChunkIndex& c = chunks[next_chunk++];
    if (!options.topics.empty() && !c.message_index_offsets.empty()) {
      const bool any = std::any_of(
          c.message_index_offsets.begin(), c.message_index_offsets.end(), [&](const auto& e) {
            const auto ch = channels.find(e.first);
            return ch == channels.end() || wanted(ch->second);
          });
      if (!any) {
        ++stats.chunks_skipped;
        return;
      }
    }
    const std::string prefix = read(c.chunk_start_offset, kPrefix);
    const uint64_t len = le64(prefix.data() + 1);
    if (static_cast<Op>(prefix[0]) != Op::kChunk || kPrefix + len != c.chunk_length) {
      fail(c.chunk_start_offset, "the chunk index points at no chunk of " +
                                     std::to_string(c.chunk_length) + " bytes");
    }
    loadChunk(read(c.chunk_start_offset + kPrefix, len), c.chunk_start_offset);
  }
};

Reader::Reader(const std::string& path, ReaderOptions options)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->options = std::move(options);
  impl_->file.open(path, std::ios::binary);
  if (!impl_->file) throw InputError("cannot open the MCAP file '" + path + "'");
  impl_->file.seekg(0, std::ios::end);
  impl_->size = static_cast<uint64_t>(impl_->file.tellg());
  impl_->open();
}

Reader::Reader(std::string name, std::string bytes, ReaderOptions options, bool)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = std::move(name);
  impl_->options = std::move(options);
  impl_->in_memory = true;
  impl_->bytes = std::move(bytes);
  impl_->size = impl_->bytes.size();
  impl_->open();
}

std::unique_ptr<Reader> Reader::fromBytes(std::string name, std::string bytes,
                                          ReaderOptions options) {
  return std::unique_ptr<Reader>(
      new Reader(std::move(name), std::move(bytes), std::move(options), true));
}

Reader::~Reader() = default;

bool Reader::next(ReadMessage& message) {
  Impl& d = *impl_;
  while (d.queue.empty() && !d.done) {
    if (d.indexed) {
      d.chunkOne();
    } else {
      d.scanOne();
    }
  }
  if (d.queue.empty()) return false;
  message = std::move(d.queue.front());
  d.queue.pop_front();
  ++d.stats.messages;
  return true;
}

const Header& Reader::header() const { return impl_->header; }
const std::map<uint16_t, Channel>& Reader::channels() const { return impl_->channels; }
const std::map<uint16_t, Schema>& Reader::schemas() const { return impl_->schemas; }
const std::optional<Statistics>& Reader::statistics() const { return impl_->statistics; }
const ReaderStats& Reader::stats() const { return impl_->stats; }
const std::string& Reader::path() const { return impl_->path; }

}  // namespace mcap
}  // namespace abi_v1
}  // namespace plugslam
