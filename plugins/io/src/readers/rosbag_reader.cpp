#include "readers/rosbag_reader.h"

#include <bzlib.h>
#include <lz4frame.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {

namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr std::size_t kMagicSize = sizeof(kMagic) - 1;

enum Op : std::uint8_t {
  kMessageData = 0x02,
  kBagHeader = 0x03,
  kIndexData = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07,
};

std::uint32_t le32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | std::uint32_t{p[1]} << 8 | std::uint32_t{p[2]} << 16 |
         std::uint32_t{p[3]} << 24;
}

struct Field {
  std::string name;
  const std::uint8_t* value;
  std::size_t size;
};

// Header fields "len name=value"; base is the file offset of p, for messages.
template <typename Fail>
std::vector<Field> parseFields(const std::uint8_t* p, std::size_t n, std::uint64_t base,
                               Fail&& fail) {
  std::vector<Field> fields;
  std::size_t i = 0;
  while (i < n) {
    if (n - i < 4)
      fail(base + i, "header field length needs 4 bytes, " + std::to_string(n - i) + " left");
    std::uint32_t len = le32(p + i);
    i += 4;
    if (len > n - i) {
      fail(base + i - 4, "header field of " + std::to_string(len) + " bytes exceeds the " +
                             std::to_string(n - i) + " bytes left in the header");
    }
    const std::uint8_t* f = p + i;
    const void* eq = std::memchr(f, '=', len);
    if (!eq) fail(base + i - 4, "header field without '=' (expected name=value)");
    std::size_t name_len = static_cast<const std::uint8_t*>(eq) - f;
    fields.push_back(Field{std::string(reinterpret_cast<const char*>(f), name_len),
                           f + name_len + 1, len - name_len - 1});
    i += len;
  }
  return fields;
}

const Field* findField(const std::vector<Field>& fields, const char* name) {
  for (const auto& f : fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

std::string fieldString(const Field* f) {
  return f ? std::string(reinterpret_cast<const char*>(f->value), f->size) : std::string();
}

}  // namespace

struct RosbagReader::Pending {
  std::uint64_t time_ns;
  std::uint64_t sequence;
  RosbagMessage message;
};

struct RosbagReader::Record {
  std::uint64_t offset{0};
  std::vector<std::uint8_t> header;
  std::vector<std::uint8_t> data;
};

RosbagReader::RosbagReader(const std::string& path, RosbagReaderOptions options)
    : path_(path), options_(std::move(options)) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    throw InputError("'" + path + "' is not a regular file; expected a ROS bag");
  }
  auto file = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*file) throw InputError("cannot open ROS bag '" + path + "': " + std::strerror(errno));
  file->seekg(0, std::ios::end);
  file_size_ = static_cast<std::uint64_t>(file->tellg());
  file->seekg(0);
  file_ = std::move(file);
  checkMagic();
}

RosbagReader::RosbagReader(std::string name, std::string bytes, RosbagReaderOptions options)
    : path_(std::move(name)), options_(std::move(options)) {
  file_size_ = bytes.size();
  file_ = std::make_unique<std::istringstream>(std::move(bytes), std::ios::binary);
  checkMagic();
}

std::unique_ptr<RosbagReader> RosbagReader::fromBytes(std::string name, std::string bytes,
                                                      RosbagReaderOptions options) {
  return std::unique_ptr<RosbagReader>(
      new RosbagReader(std::move(name), std::move(bytes), std::move(options)));
}

void RosbagReader::checkMagic() {
  char magic[kMagicSize] = {};
  file_->read(magic, kMagicSize);
  if (static_cast<std::size_t>(file_->gcount()) != kMagicSize ||
      std::memcmp(magic, kMagic, kMagicSize) != 0) {
    if (std::memcmp(magic, "#ROSBAG V", 9) == 0) {
      std::string version(magic, magic + kMagicSize - 1);
      for (char& c : version) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
      }
      fail(0, "unsupported bag version '" + version + "'; expected #ROSBAG V2.0");
    }
    fail(0, "not a ROS bag: expected the magic line '#ROSBAG V2.0'");
  }
  position_ = kMagicSize;
}

RosbagReader::~RosbagReader() = default;

void RosbagReader::fail(std::uint64_t offset, const std::string& message) const {
  throw ParseError(path_, 0, "byte offset " + std::to_string(offset) + ": " + message);
}

bool RosbagReader::readTopRecord(Record& record) {
  if (position_ == file_size_) return false;
  record.offset = position_;
  auto readLength = [&](const char* what) -> std::uint32_t {
    std::uint64_t left = file_size_ - position_;
    if (left < 4) {
      fail(position_, std::string(what) + " length needs 4 bytes but the file ends after " +
                          std::to_string(left) + " (truncated bag)");
    }
    std::uint8_t b[4];
    file_->read(reinterpret_cast<char*>(b), 4);
    if (!*file_) fail(position_, "read error");
    position_ += 4;
    return le32(b);
  };
  auto readBytes = [&](std::vector<std::uint8_t>& out, std::uint32_t n, const char* what) {
    std::uint64_t left = file_size_ - position_;
    if (n > left) {
      fail(position_ - 4, std::string(what) + " of " + std::to_string(n) + " bytes exceeds the " +
                              std::to_string(left) +
                              " bytes left in the file (truncated or corrupt bag)");
    }
    if (n > options_.max_record_bytes) {
      fail(position_ - 4, std::string(what) + " of " + std::to_string(n) +
                              " bytes exceeds the limit of " +
                              std::to_string(options_.max_record_bytes));
    }
    out.resize(n);
    if (n) file_->read(reinterpret_cast<char*>(out.data()), n);
    if (!*file_) fail(position_, "read error");
    position_ += n;
  };
  std::uint32_t header_len = readLength("record header");
  readBytes(record.header, header_len, "record header");
  std::uint32_t data_len = readLength("record data");
  readBytes(record.data, data_len, "record data");
  return true;
}

void RosbagReader::addConnection(std::uint32_t id, const std::string& topic,
                                 const std::uint8_t* data, std::size_t size, std::uint64_t offset) {
  if (connections_.count(id)) return;
  auto fields = parseFields(data, size, offset,
                            [this](std::uint64_t o, const std::string& m) { fail(o, m); });
  auto c = std::make_unique<RosbagConnection>();
  c->id = id;
  c->topic = topic;
  std::string t = fieldString(findField(fields, "topic"));
  if (c->topic.empty()) c->topic = t;
  c->type = fieldString(findField(fields, "type"));
  c->md5sum = fieldString(findField(fields, "md5sum"));
  c->message_definition = fieldString(findField(fields, "message_definition"));
  c->callerid = fieldString(findField(fields, "callerid"));
  if (c->type.empty()) fail(offset, "connection " + std::to_string(id) + " has no type field");
  connections_.emplace(id, std::move(c));
}

void RosbagReader::addMessage(std::uint32_t conn, RosTime time, const std::uint8_t* data,
                              std::size_t size, std::uint64_t offset) {
  chunk_min_ns_ = std::min(chunk_min_ns_, time.toNsec());
  auto it = connections_.find(conn);
  if (it == connections_.end()) {
    fail(offset, "message refers to connection " + std::to_string(conn) +
                     ", which no earlier connection record defines");
  }
  if (!options_.topics.empty() && !options_.topics.count(it->second->topic)) {
    ++stats_.filtered;
    return;
  }
  auto p = std::make_unique<Pending>();
  p->time_ns = time.toNsec();
  p->sequence = sequence_++;
  p->message.connection = it->second.get();
  p->message.time = time;
  p->message.data.assign(data, data + size);
  p->message.file_offset = offset;
  heap_.push_back(std::move(p));
  std::push_heap(heap_.begin(), heap_.end(), later);
}

bool RosbagReader::later(const std::unique_ptr<Pending>& a, const std::unique_ptr<Pending>& b) {
  if (a->time_ns != b->time_ns) return a->time_ns > b->time_ns;
  return a->sequence > b->sequence;
}

namespace {

// Decompressors grow the output as it is produced, so a lying "size" field never allocates more
// than the stream really holds (plus one doubling step).
template <typename Fail>
void bz2Decompress(const std::vector<std::uint8_t>& in, std::size_t expected,
                   std::vector<std::uint8_t>& out, Fail&& fail) {
  bz_stream s;
  std::memset(&s, 0, sizeof s);
  if (BZ2_bzDecompressInit(&s, 0, 0) != BZ_OK) fail("cannot initialise bz2");
  out.resize(std::min<std::size_t>(expected, in.size() * 8 + 65536));
  s.next_in = const_cast<char*>(reinterpret_cast<const char*>(in.data()));
  s.avail_in = static_cast<unsigned>(in.size());
  std::size_t produced = 0;
  int rc = BZ_OK;
  for (;;) {
    if (produced == out.size()) {
      if (out.size() >= expected) {
        // Room is exhausted: one probe byte tells whether the stream holds more than declared.
        char probe;
        s.next_out = &probe;
        s.avail_out = 1;
        rc = BZ2_bzDecompress(&s);
        bool more = s.avail_out == 0;
        BZ2_bzDecompressEnd(&s);
        if (more)
          fail("bz2 chunk holds more than its declared " + std::to_string(expected) + " bytes");
        if (rc != BZ_STREAM_END && rc != BZ_OK)
          fail("bz2 chunk is corrupt (code " + std::to_string(rc) + ")");
        if (rc != BZ_STREAM_END) fail("bz2 chunk is truncated");
        return;
      }
      out.resize(std::min(expected, out.size() * 2));
    }
    s.next_out = reinterpret_cast<char*>(out.data() + produced);
    s.avail_out = static_cast<unsigned>(out.size() - produced);
    rc = BZ2_bzDecompress(&s);
    produced = out.size() - s.avail_out;
    if (rc == BZ_STREAM_END) break;
    if (rc != BZ_OK) {
      BZ2_bzDecompressEnd(&s);
      fail("bz2 chunk is corrupt (code " + std::to_string(rc) + ")");
    }
    if (s.avail_in == 0 && s.avail_out != 0) {
      BZ2_bzDecompressEnd(&s);
      fail("bz2 chunk is truncated");
    }
  }
  BZ2_bzDecompressEnd(&s);
  if (produced != expected) {
    fail("bz2 chunk decompressed to " + std::to_string(produced) + " bytes; its header says " +
         std::to_string(expected));
  }
  out.resize(produced);
}

template <typename Fail>
void lz4Decompress(const std::vector<std::uint8_t>& in, std::size_t expected,
                   std::vector<std::uint8_t>& out, Fail&& fail) {
  LZ4F_dctx* ctx = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&ctx, LZ4F_VERSION))) {
    fail("cannot initialise lz4");
  }
  struct Free {
    LZ4F_dctx* c;
    ~Free() { LZ4F_freeDecompressionContext(c); }
  } guard{ctx};
  out.resize(std::min<std::size_t>(expected, in.size() * 8 + 65536));
  std::size_t produced = 0, consumed = 0;
  std::size_t hint = 1;
  while (consumed < in.size()) {
    if (produced == out.size()) {
      if (out.size() >= expected) {
        fail("lz4 chunk holds more than its declared " + std::to_string(expected) + " bytes");
      }
      out.resize(std::min(expected, out.size() * 2));
    }
    std::size_t dst = out.size() - produced;
    std::size_t src = in.size() - consumed;
    hint = LZ4F_decompress(ctx, out.data() + produced, &dst, in.data() + consumed, &src, nullptr);
    if (LZ4F_isError(hint)) fail(std::string("lz4 chunk is corrupt: ") + LZ4F_getErrorName(hint));
    produced += dst;
    consumed += src;
    if (hint == 0) break;
    if (src == 0 && dst == 0 && produced < out.size()) fail("lz4 chunk makes no progress");
  }
  if (hint != 0) fail("lz4 chunk is truncated");
  if (produced != expected) {
    fail("lz4 chunk decompressed to " + std::to_string(produced) + " bytes; its header says " +
         std::to_string(expected));
  }
  out.resize(produced);
}
}  // namespace

void RosbagReader::loadChunk(const Record& record) {
  auto failHere = [&](std::uint64_t o, const std::string& m) { fail(o, m); };
  auto fields =
      parseFields(record.header.data(), record.header.size(), record.offset + 4, failHere);
  const Field* comp = findField(fields, "compression");
  const Field* size = findField(fields, "size");
  if (!comp || !size || size->size != 4) {
    fail(record.offset, "chunk record needs 'compression' and a 4-byte 'size' field");
  }
  std::string compression = fieldString(comp);
  std::size_t expected = le32(size->value);
  if (expected > options_.max_record_bytes) {
    fail(record.offset, "chunk declares " + std::to_string(expected) +
                            " uncompressed bytes, above the limit of " +
                            std::to_string(options_.max_record_bytes));
  }
  ++stats_.chunks;
  ++stats_.compression[compression];
  auto chunkFail = [&](const std::string& m) {
    fail(record.offset, "chunk (" + compression + "): " + m);
  };
  const std::vector<std::uint8_t>* plain = &record.data;
  std::vector<std::uint8_t> buffer;
  if (compression == "none") {
    if (record.data.size() != expected) {
      chunkFail("holds " + std::to_string(record.data.size()) + " bytes; its header says " +
                std::to_string(expected));
    }
  } else if (compression == "bz2") {
    bz2Decompress(record.data, expected, buffer, chunkFail);
    plain = &buffer;
  } else if (compression == "lz4") {
    lz4Decompress(record.data, expected, buffer, chunkFail);
    plain = &buffer;
  } else {
    fail(record.offset,
         "unknown chunk compression '" + compression + "'; expected none, bz2 or lz4");
  }
  parseInner(plain->data(), plain->size(), record.offset);
}

void RosbagReader::parseInner(const std::uint8_t* data, std::size_t size, std::uint64_t base) {
  // Inner offsets are reported as "chunk at <base> + <offset>" through the outer record offset.
  auto failInner = [&](std::uint64_t inner, const std::string& m) {
    fail(base, "inside the chunk at byte " + std::to_string(inner) + ": " + m);
  };
  std::size_t i = 0;
  std::size_t start = 0;
  // The record's header or data (`what`) at i: a uint32 length `n`, then n bytes of the chunk.
  auto block = [&](const char* what, std::uint32_t& n) {
    if (size - i < 4)
      failInner(i, std::string("record ") + what + " length needs 4 bytes (chunk truncated)");
    n = le32(data + i);
    i += 4;
    if (n > size - i)
      failInner(start, std::string("record ") + what + " of " + std::to_string(n) +
                           " bytes exceeds the chunk");
    const std::uint8_t* p = data + i;
    i += n;
    return p;
  };
  while (i < size) {
    start = i;
    std::uint32_t hl = 0, dl = 0;
    const std::uint8_t* header = block("header", hl);
    const std::uint8_t* body = block("data", dl);
    auto fields = parseFields(header, hl, start + 4, failInner);
    const Field* op = findField(fields, "op");
    if (!op || op->size != 1) failInner(start, "record without a 1-byte 'op' field");
    if (op->value[0] == kConnection) {
      const Field* conn = findField(fields, "conn");
      if (!conn || conn->size != 4) failInner(start, "connection record needs a 4-byte 'conn'");
      addConnection(le32(conn->value), fieldString(findField(fields, "topic")), body, dl, base);
    } else if (op->value[0] == kMessageData) {
      const Field* conn = findField(fields, "conn");
      const Field* time = findField(fields, "time");
      if (!conn || conn->size != 4 || !time || time->size != 8) {
        failInner(start, "message record needs a 4-byte 'conn' and an 8-byte 'time'");
      }
      RosTime t{le32(time->value), le32(time->value + 4)};
      addMessage(le32(conn->value), t, body, dl, base);
    } else {
      failInner(start, "unexpected record op " + std::to_string(op->value[0]) +
                           " inside a chunk; expected connection (7) or message (2)");
    }
  }
}

bool RosbagReader::next(RosbagMessage& message) {
  Record record;
  for (;;) {
    // A pending message is safe to return once a later chunk started after it: bags are written
    // in roughly increasing time, so only neighbouring chunks overlap.
    if (!heap_.empty() && (at_end_ || heap_.front()->time_ns <= watermark_ns_)) {
      std::pop_heap(heap_.begin(), heap_.end(), later);
      std::unique_ptr<Pending> p = std::move(heap_.back());
      heap_.pop_back();
      message = std::move(p->message);
      message.out_of_order = returned_any_ && p->time_ns < last_returned_ns_;
      if (message.out_of_order) {
        ++stats_.out_of_order;
      } else {
        last_returned_ns_ = p->time_ns;
      }
      returned_any_ = true;
      ++stats_.messages;
      return true;
    }
    if (at_end_) return false;
    if (!readTopRecord(record)) {
      at_end_ = true;
      continue;
    }
    auto failHere = [&](std::uint64_t o, const std::string& m) { fail(o, m); };
    auto fields =
        parseFields(record.header.data(), record.header.size(), record.offset + 4, failHere);
    const Field* op = findField(fields, "op");
    if (!op || op->size != 1) fail(record.offset, "record without a 1-byte 'op' field");
    std::uint64_t min_time = UINT64_MAX;
    switch (op->value[0]) {
      case kBagHeader:
      case kIndexData:
      case kChunkInfo:
        break;
      case kChunk:
        chunk_min_ns_ = UINT64_MAX;
        loadChunk(record);
        min_time = chunk_min_ns_;
        break;
      case kConnection: {
        const Field* conn = findField(fields, "conn");
        if (!conn || conn->size != 4)
          fail(record.offset, "connection record needs a 4-byte 'conn'");
        addConnection(le32(conn->value), fieldString(findField(fields, "topic")),
                      record.data.data(), record.data.size(), record.offset);
        break;
      }
      case kMessageData: {
        const Field* conn = findField(fields, "conn");
        const Field* time = findField(fields, "time");
        if (!conn || conn->size != 4 || !time || time->size != 8) {
          fail(record.offset, "message record needs a 4-byte 'conn' and an 8-byte 'time'");
        }
        RosTime t{le32(time->value), le32(time->value + 4)};
        chunk_min_ns_ = UINT64_MAX;
        addMessage(le32(conn->value), t, record.data.data(), record.data.size(), record.offset);
        min_time = chunk_min_ns_;
        break;
      }
      default:
        fail(record.offset,
             "unknown record op " + std::to_string(op->value[0]) + "; expected 2 to 7 (bag v2.0)");
    }
    if (min_time != UINT64_MAX) watermark_ns_ = min_time;
  }
}

std::vector<RosbagTopicInfo> summarizeRosbag(const std::string& path) {
  RosbagReader reader(path);
  std::map<std::string, RosbagTopicInfo> by_topic;
  RosbagMessage m;
  while (reader.next(m)) {
    auto& info = by_topic[m.connection->topic];
    double t = m.time.toSec();
    if (info.count == 0) {
      info.topic = m.connection->topic;
      info.type = m.connection->type;
      info.first_time = info.last_time = t;
    }
    ++info.count;
    info.first_time = std::min(info.first_time, t);
    info.last_time = std::max(info.last_time, t);
  }
  std::vector<RosbagTopicInfo> out;
  for (auto& kv : by_topic) out.push_back(kv.second);
  return out;
}

}  // namespace io
}  // namespace plugslam
