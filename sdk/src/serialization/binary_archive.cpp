// The binary back-end. Layout (all integers little-endian):
//   header:  "PLSB" | u32 format version | u64 payload length | u32 CRC-32 of the payload
//   payload: exactly one value
//   value:   u8 tag, then
//     false/true: nothing            int: zigzag varint        uint: varint
//     double: 8 bytes                string: varint length, bytes
//     doubles: varint n, 8*n bytes (the compact blob)
//     array: varint n, n values      object: u32 n, n x (varint key length, key bytes, value)
// The object count is fixed-width so the writer can patch it when the object closes. Values are
// self-delimiting, so a reader can index an object's fields and find them by name. The whole
// payload is length- and checksum-verified and structurally validated before anything is read,
// and no count is trusted before it is checked against the bytes actually present.
#include <array>
#include <cstring>
#include <istream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "plugslam/errors.h"
#include "serialization/backends.h"
#include "serialization/reader_frames.h"
#include "serialization/writer_frames.h"

namespace plugslam {
inline namespace abi_v1 {
namespace serialization {

namespace {

enum Tag : std::uint8_t {
  kFalse = 1,
  kTrue = 2,
  kInt = 3,
  kUInt = 4,
  kDouble = 5,
  kString = 6,
  kDoubles = 7,
  kArray = 8,
  kObject = 9,
};

const char* tagName(std::uint8_t tag) {
  switch (tag) {
    case kFalse:
    case kTrue:
      return "a bool";
    case kInt:
      return "a signed integer";
    case kUInt:
      return "an unsigned integer";
    case kDouble:
      return "a double";
    case kString:
      return "a string";
    case kDoubles:
      return "a blob of doubles";
    case kArray:
      return "an array";
    case kObject:
      return "an object";
    default:
      return "an unknown value tag";
  }
}

constexpr bool kLittleEndianHost = __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__;
constexpr std::size_t kHeaderSize = 4 + 4 + 8 + 4;

void putLE(std::string& buf, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) buf.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

std::uint64_t getLE(const char* p, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i)
    v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(p[i])) << (8 * i);
  return v;
}

void putVarint(std::string& buf, std::uint64_t v) {
  while (v >= 0x80) {
    buf.push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  buf.push_back(static_cast<char>(v));
}

std::uint64_t doubleBits(double d) {
  std::uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}

double bitsDouble(std::uint64_t u) {
  double d;
  std::memcpy(&d, &u, sizeof d);
  return d;
}

// ---------------------------------------------------------------------------------------------

class BinaryOut final : public OutArchive {
 public:
  explicit BinaryOut(std::ostream& out) : out_(out) {}

  void beginObject() override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kObject));
    frames_.openObject().patch_pos = buf_.size();
    putLE(buf_, 0, 4);
  }

  void endObject() override {
    const WriterFrames::Frame f = frames_.closeObject();
    if (f.count > std::numeric_limits<std::uint32_t>::max())
      frames_.misuse("more than 2^32 fields");
    for (int i = 0; i < 4; ++i)
      buf_[f.patch_pos + i] = static_cast<char>((f.count >> (8 * i)) & 0xff);
  }

  void key(const std::string& name) override {
    WriterFrames::Frame& f = frames_.acceptKey(name);
    putVarint(buf_, name.size());
    buf_ += name;
    f.key_pending = true;
  }

  void beginArray(std::size_t size) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kArray));
    putVarint(buf_, size);
    frames_.openArray(size);
  }

  void endArray() override { frames_.closeArray(); }

  void writeBool(bool value) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(value ? kTrue : kFalse));
  }

  void writeInt(std::int64_t value) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kInt));
    const std::uint64_t u = static_cast<std::uint64_t>(value);
    putVarint(buf_, (u << 1) ^ (value < 0 ? ~std::uint64_t{0} : 0));  // zigzag
  }

  void writeUInt(std::uint64_t value) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kUInt));
    putVarint(buf_, value);
  }

  void writeDouble(double value) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kDouble));
    putLE(buf_, doubleBits(value), 8);
  }

  void writeString(const std::string& value) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kString));
    putVarint(buf_, value.size());
    buf_ += value;
  }

  void writeDoubles(const double* data, std::size_t n) override {
    frames_.beforeValue();
    buf_.push_back(static_cast<char>(kDoubles));
    putVarint(buf_, n);
    if constexpr (kLittleEndianHost) {
      buf_.append(reinterpret_cast<const char*>(data), n * sizeof(double));
    } else {
      for (std::size_t i = 0; i < n; ++i) putLE(buf_, doubleBits(data[i]), 8);
    }
  }

  void finish() override {
    frames_.checkFinish();
    std::string header(kBinaryMagic, kBinaryMagic + 4);
    putLE(header, kBinaryVersion, 4);
    putLE(header, buf_.size(), 8);
    putLE(header, crc32(0, buf_.data(), buf_.size()), 4);
    out_.write(header.data(), static_cast<std::streamsize>(header.size()));
    out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
    out_.flush();
    frames_.markFinished();
    if (!out_) throw Error("cannot write the binary archive: the output stream failed");
    std::string().swap(buf_);
  }

 private:
  std::ostream& out_;
  std::string buf_;
  WriterFrames frames_{"binary"};
};

// ---------------------------------------------------------------------------------------------

class BinaryIn final : public InArchive {
 public:
  BinaryIn(std::istream& in, std::string source) : source_(std::move(source)) {
    readPayload(in);
    std::size_t pos = 0;
    const std::size_t end = skip(pos, 0);
    if (end != data_.size()) {
      pos_ = end;
      failAt(end, std::to_string(data_.size() - end) + " unexpected bytes after the root value");
    }
  }

  void beginObject() override {
    slot();
    expectTag(kObject);
    if (frames_.depth() >= kMaxDepth) fail("objects and arrays nested too deep");
    const std::uint32_t n = static_cast<std::uint32_t>(getLE(take(4), 4));
    Frame f;
    f.object = true;
    f.segment = frames_.takeSegment();
    f.keys.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::size_t len = takeCount(1, "field name");
      std::string k(take(len), len);
      if (!f.index.emplace(k, pos_).second) fail("duplicate field '" + k + "'");
      f.keys.push_back(std::move(k));
      pos_ = skip(pos_, frames_.depth() + 1);
    }
    f.end = pos_;
    frames_.push(std::move(f));
  }

  void endObject() override {
    pos_ = frames_.closing(true).end;
    frames_.pop();
  }

  void key(const std::string& name) override {
    const Frame& f = frames_.keyObject();
    auto it = f.index.find(name);
    if (it == f.index.end()) fail(Frames::missingField(name, f.keys));
    pending_pos_ = it->second;
    frames_.select(name);
  }

  bool hasKey(const std::string& name) const override { return frames_.hasKey(name); }

  std::vector<std::string> keys() const override { return frames_.keys(); }

  std::size_t beginArray() override {
    slot();
    expectTag(kArray);
    if (frames_.depth() >= kMaxDepth) fail("objects and arrays nested too deep");
    Frame f;
    f.object = false;
    f.count = takeCount(1, "array");
    f.segment = frames_.takeSegment();
    frames_.push(std::move(f));
    return frames_.top().count;
  }

  void endArray() override {
    Frame& f = frames_.closing(false);
    for (; f.next < f.count; ++f.next) pos_ = skip(pos_, frames_.depth());
    frames_.pop();
  }

  bool readBool() override {
    slot();
    const std::uint8_t tag = peekTag();
    if (tag != kTrue && tag != kFalse) mismatch("a bool", tag);
    ++pos_;
    return tag == kTrue;
  }

  std::int64_t readInt() override {
    slot();
    const std::uint8_t tag = peekTag();
    if (tag == kInt) {
      ++pos_;
      const std::uint64_t z = varint();
      return static_cast<std::int64_t>((z >> 1) ^ (~(z & 1) + 1));
    }
    if (tag == kUInt) {
      ++pos_;
      const std::uint64_t u = varint();
      if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        fail("integer " + std::to_string(u) + " does not fit a signed 64-bit integer");
      }
      return static_cast<std::int64_t>(u);
    }
    mismatch("an integer", tag);
  }

  std::uint64_t readUInt() override {
    slot();
    const std::uint8_t tag = peekTag();
    if (tag == kUInt) {
      ++pos_;
      return varint();
    }
    if (tag == kInt) {
      ++pos_;
      const std::uint64_t z = varint();
      const auto v = static_cast<std::int64_t>((z >> 1) ^ (~(z & 1) + 1));
      if (v < 0) fail("expected an unsigned integer, found " + std::to_string(v));
      return static_cast<std::uint64_t>(v);
    }
    mismatch("an unsigned integer", tag);
  }

  double readDouble() override {
    slot();
    const std::uint8_t tag = peekTag();
    if (tag != kDouble) mismatch("a double", tag);
    ++pos_;
    return bitsDouble(getLE(take(8), 8));
  }

  std::string readString() override {
    slot();
    expectTag(kString);
    const std::size_t len = takeCount(1, "string");
    return std::string(take(len), len);
  }

  void readDoubles(const std::function<double*(std::size_t n)>& storage) override {
    slot();
    expectTag(kDoubles);
    const std::size_t n = takeCount(8, "blob of doubles");
    const char* src = take(n * 8);
    double* dst = storage(n);
    if (n == 0) return;
    if constexpr (kLittleEndianHost) {
      std::memcpy(dst, src, n * 8);
    } else {
      for (std::size_t i = 0; i < n; ++i) dst[i] = bitsDouble(getLE(src + 8 * i, 8));
    }
  }

  [[noreturn]] void fail(const std::string& message) const override { failAt(pos_, message); }

 private:
  struct Frame {
    bool object = false;
    std::string segment;
    std::vector<std::string> keys;
    std::unordered_map<std::string, std::size_t> index;
    std::size_t end = 0;
    std::size_t count = 0;
    std::size_t next = 0;
  };

  using Frames = ReaderFrames<Frame>;

  [[noreturn]] void failAt(std::size_t pos, const std::string& message) const {
    throw ParseError(source_, 0,
                     "binary archive, at " + frames_.path() + " (payload byte " +
                         std::to_string(pos) + "): " + message);
  }

  [[noreturn]] void headerFail(const std::string& message) const {
    throw ParseError(source_, 0, "binary archive: " + message);
  }

  void readPayload(std::istream& in) {
    char header[kHeaderSize];
    in.read(header, kHeaderSize);
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got == 0) headerFail("the input is empty (expected a plugslam binary archive)");
    if (got >= 4 && std::memcmp(header, kBinaryMagic, 4) != 0) {
      headerFail("not a plugslam binary archive (the first bytes are not \"PLSB\")");
    }
    if (got < kHeaderSize) {
      headerFail("truncated header: " + std::to_string(got) + " of " + std::to_string(kHeaderSize) +
                 " bytes");
    }
    const auto version = static_cast<std::uint32_t>(getLE(header + 4, 4));
    if (version != kBinaryVersion) {
      headerFail("format version " + std::to_string(version) +
                 " is not supported (this build reads version " + std::to_string(kBinaryVersion) +
                 ")");
    }
    const std::uint64_t length = getLE(header + 8, 8);
    const auto crc = static_cast<std::uint32_t>(getLE(header + 16, 4));
    // Read in chunks so a corrupted length never allocates more than the input really holds.
    std::array<char, 1 << 16> chunk;
    std::uint64_t remaining = length;
    while (remaining > 0) {
      const std::size_t want =
          static_cast<std::size_t>(std::min<std::uint64_t>(remaining, chunk.size()));
      in.read(chunk.data(), static_cast<std::streamsize>(want));
      const auto n = static_cast<std::size_t>(in.gcount());
      data_.append(chunk.data(), n);
      if (n < want) {
        headerFail("truncated: the header announces " + std::to_string(length) +
                   " payload bytes, the input holds " + std::to_string(data_.size()));
      }
      remaining -= n;
    }
    if (crc32(0, data_.data(), data_.size()) != crc) {
      headerFail("corrupted: the payload checksum does not match the header");
    }
  }

  // Bounds-checked cursor primitives on data_ at pos_.
  void need(std::size_t pos, std::size_t n) const {
    if (n > data_.size() - pos) failAt(pos, "unexpected end of the payload");
  }

  const char* take(std::size_t n) {
    need(pos_, n);
    const char* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }

  std::uint64_t varintAt(std::size_t& pos) const {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      need(pos, 1);
      const auto b = static_cast<std::uint8_t>(data_[pos++]);
      if (shift == 63 && b > 1) failAt(pos - 1, "integer overflows 64 bits");
      v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
      if ((b & 0x80) == 0) return v;
    }
    failAt(pos, "integer encoding longer than 10 bytes");
  }

  std::uint64_t varint() { return varintAt(pos_); }

  // A count of items each taking at least `min_bytes`: rejected unless that many bytes remain.
  std::size_t countAt(std::size_t& pos, std::size_t min_bytes, const char* what) const {
    const std::uint64_t n = varintAt(pos);
    if (n > (data_.size() - pos) / min_bytes) {
      failAt(pos, std::string(what) + " of " + std::to_string(n) +
                      " items is longer than the rest of the payload");
    }
    return static_cast<std::size_t>(n);
  }

  std::size_t takeCount(std::size_t min_bytes, const char* what) {
    return countAt(pos_, min_bytes, what);
  }

  std::uint8_t peekTag() const {
    need(pos_, 1);
    return static_cast<std::uint8_t>(data_[pos_]);
  }

  void expectTag(std::uint8_t want) {
    const std::uint8_t tag = peekTag();
    if (tag != want) mismatch(tagName(want), tag);
    ++pos_;
  }

  [[noreturn]] void mismatch(const char* expected, std::uint8_t found) const {
    fail(std::string("expected ") + expected + ", found " + tagName(found));
  }

  // Returns the end of the value starting at pos; validates its structure on the way.
  std::size_t skip(std::size_t pos, int depth) const {
    if (depth > kMaxDepth) failAt(pos, "objects and arrays nested too deep");
    need(pos, 1);
    const auto tag = static_cast<std::uint8_t>(data_[pos++]);
    switch (tag) {
      case kFalse:
      case kTrue:
        return pos;
      case kInt:
      case kUInt:
        varintAt(pos);
        return pos;
      case kDouble:
        need(pos, 8);
        return pos + 8;
      case kString: {
        const std::size_t len = countAt(pos, 1, "string");
        return pos + len;
      }
      case kDoubles: {
        const std::size_t n = countAt(pos, 8, "blob of doubles");
        return pos + 8 * n;
      }
      case kArray: {
        const std::size_t n = countAt(pos, 1, "array");
        for (std::size_t i = 0; i < n; ++i) pos = skip(pos, depth + 1);
        return pos;
      }
      case kObject: {
        need(pos, 4);
        const std::uint64_t n = getLE(data_.data() + pos, 4);
        pos += 4;
        if (n > (data_.size() - pos) / 2) failAt(pos, "object field count exceeds the payload");
        for (std::uint64_t i = 0; i < n; ++i) {
          const std::size_t len = countAt(pos, 1, "field name");
          pos += len;
          pos = skip(pos, depth + 1);
        }
        return pos;
      }
      default:
        failAt(pos - 1, "unknown value tag " + std::to_string(tag));
    }
  }

  // Positions pos_ on the next value to read and records its path segment for messages.
  void slot() {
    switch (frames_.next()) {
      case Frames::Next::kRoot:
        pos_ = 0;
        return;
      case Frames::Next::kField:
        pos_ = pending_pos_;
        return;
      case Frames::Next::kElement:
        if (const std::string past = frames_.pastEnd(); !past.empty()) fail(past);
        frames_.element();  // elements follow each other: pos_ is at this one already
        return;
    }
  }

  std::string source_;
  std::string data_;
  std::size_t pos_ = 0;
  Frames frames_{"binary"};
  std::size_t pending_pos_ = 0;  // where the field that key() selected starts
};

std::array<std::uint32_t, 256> makeCrcTable() {
  std::array<std::uint32_t, 256> t{};
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    t[i] = c;
  }
  return t;
}

}  // namespace

std::uint32_t crc32(std::uint32_t crc, const void* data, std::size_t n) {
  static const std::array<std::uint32_t, 256> table = makeCrcTable();
  const auto* p = static_cast<const std::uint8_t*>(data);
  crc = ~crc;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xff] ^ (crc >> 8);
  return ~crc;
}

std::unique_ptr<OutArchive> makeBinaryOut(std::ostream& out) {
  return std::make_unique<BinaryOut>(out);
}

std::unique_ptr<InArchive> makeBinaryIn(std::istream& in, const std::string& source) {
  return std::make_unique<BinaryIn>(in, source);
}

}  // namespace serialization
}  // namespace abi_v1
}  // namespace plugslam
