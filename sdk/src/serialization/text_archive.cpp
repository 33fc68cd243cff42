// The text back-end: YAML through yaml-cpp (kept out of the public headers). A document is
//   plugslam_archive: 1
//   data: <the root value>
// Objects are block maps, arrays block sequences, blobs of doubles flow sequences. Doubles are
// written in the shortest form that reads back to the same value (std::to_chars), so text round
// trips are exact; NaN is written as .nan (its payload bits are not kept).
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <cmath>
#include <istream>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "plugslam/errors.h"
#include "plugslam/yaml_load.h"
#include "serialization/backends.h"
#include "serialization/reader_frames.h"
#include "serialization/writer_frames.h"

namespace plugslam {
inline namespace abi_v1 {
namespace serialization {

namespace {

constexpr const char* kVersionKey = "plugslam_archive";
constexpr const char* kDataKey = "data";

std::string formatDouble(double v) {
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

bool validUtf8(const std::string& s) {
  std::size_t i = 0;
  const std::size_t n = s.size();
  while (i < n) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra;
    std::uint32_t cp;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xe0) == 0xc0) {
      extra = 1;
      cp = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      extra = 2;
      cp = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + static_cast<std::size_t>(extra) >= n) return false;
    for (int k = 1; k <= extra; ++k) {
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3f);
    }
    static const std::uint32_t kMin[] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    i += static_cast<std::size_t>(extra) + 1;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------

class TextOut final : public OutArchive {
 public:
  explicit TextOut(std::ostream& out) : out_(out), em_(out) {
    em_.SetIndent(2);
    em_ << YAML::BeginMap << YAML::Key << kVersionKey << YAML::Value << kTextVersion << YAML::Key
        << kDataKey << YAML::Value;
  }

  void beginObject() override {
    frames_.beforeValue();
    em_ << YAML::Block << YAML::BeginMap;
    frames_.openObject();
  }

  void endObject() override {
    frames_.closeObject();
    em_ << YAML::EndMap;
  }

  void key(const std::string& name) override {
    WriterFrames::Frame& f = frames_.acceptKey(name);
    if (!validUtf8(name)) {
      throw Error("the text archive needs UTF-8 field names; '" + name +
                  "' is not valid UTF-8 (use the binary format)");
    }
    em_ << YAML::Key << name << YAML::Value;
    f.key_pending = true;
  }

  void beginArray(std::size_t size) override {
    frames_.beforeValue();
    em_ << YAML::Block << YAML::BeginSeq;
    frames_.openArray(size);
  }

  void endArray() override {
    frames_.closeArray();
    em_ << YAML::EndSeq;
  }

  void writeBool(bool value) override {
    frames_.beforeValue();
    em_ << (value ? "true" : "false");
  }

  void writeInt(std::int64_t value) override {
    frames_.beforeValue();
    em_ << std::to_string(value);
  }

  void writeUInt(std::uint64_t value) override {
    frames_.beforeValue();
    em_ << std::to_string(value);
  }

  void writeDouble(double value) override {
    frames_.beforeValue();
    em_ << formatDouble(value);
  }

  void writeString(const std::string& value) override {
    frames_.beforeValue();
    if (!validUtf8(value)) {
      throw Error(
          "the text archive needs UTF-8 strings; a string value is not valid UTF-8 "
          "(use the binary format)");
    }
    // Quoted so a string that looks like a number, bool or null stays a string for readers
    // that do not know the schema.
    em_ << YAML::DoubleQuoted << value;
  }

  void writeDoubles(const double* data, std::size_t n) override {
    frames_.beforeValue();
    em_ << YAML::Flow << YAML::BeginSeq;
    for (std::size_t i = 0; i < n; ++i) em_ << formatDouble(data[i]);
    em_ << YAML::EndSeq;
  }

  void finish() override {
    frames_.checkFinish();
    em_ << YAML::EndMap;
    frames_.markFinished();
    if (!em_.good()) throw Error("cannot write the text archive: " + em_.GetLastError());
    out_ << '\n';
    out_.flush();
    if (!out_) throw Error("cannot write the text archive: the output stream failed");
  }

 private:
  std::ostream& out_;
  YAML::Emitter em_;
  WriterFrames frames_{"text"};
};

// ---------------------------------------------------------------------------------------------

const char* kindName(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Scalar:
      return "a scalar";
    case YAML::NodeType::Sequence:
      return "a sequence";
    case YAML::NodeType::Map:
      return "a map";
    default:
      return "an undefined node";
  }
}

class TextIn final : public InArchive {
 public:
  TextIn(std::istream& in, std::string source) : source_(std::move(source)) {
    YAML::Node loaded;
    try {
      loaded.reset(loadYaml(in));
    } catch (const YAML::Exception& e) {
      throw ParseError(source_, e.mark.is_null() ? 0 : e.mark.line + 1,
                       "text archive: invalid YAML: " + e.msg);
    }
    const YAML::Node& doc = loaded;  // const: operator[] must not insert missing keys
    if (!doc.IsMap()) {
      throw ParseError(source_, 0,
                       "text archive: expected a map with '" + std::string(kVersionKey) +
                           "' and '" + kDataKey + "', found " + kindName(doc));
    }
    const YAML::Node version = doc[kVersionKey];
    if (!version || !version.IsScalar()) {
      throw ParseError(
          source_, lineOf(doc),
          std::string("text archive: missing '") + kVersionKey + "' (not a plugslam text archive)");
    }
    if (version.Scalar() != std::to_string(kTextVersion)) {
      throw ParseError(source_, lineOf(version),
                       "text archive: format version " + version.Scalar() +
                           " is not supported (this build reads version " +
                           std::to_string(kTextVersion) + ")");
    }
    const YAML::Node data = doc[kDataKey];
    if (!data.IsDefined()) {
      throw ParseError(source_, lineOf(doc),
                       std::string("text archive: missing '") + kDataKey + "'");
    }
    root_.reset(data);
  }

  void beginObject() override {
    YAML::Node n = slot();
    if (!n.IsMap()) fail(std::string("expected an object (a map), found ") + kindName(n));
    if (frames_.depth() >= kMaxDepth) fail("objects and arrays nested too deep");
    Frame f;
    f.node.reset(n);
    f.object = true;
    f.segment = frames_.takeSegment();
    for (const auto& kv : n) {
      if (!kv.first.IsScalar()) {
        cur_.reset(kv.first);
        fail("field names must be scalars, found " + std::string(kindName(kv.first)));
      }
      const std::string& k = kv.first.Scalar();
      if (!f.index.emplace(k, f.keys.size()).second) {
        cur_.reset(kv.first);
        fail("duplicate field '" + k + "'");
      }
      f.keys.push_back(k);
      f.values.push_back(kv.second);
    }
    frames_.push(std::move(f));
  }

  void endObject() override {
    cur_.reset(frames_.closing(true).node);
    frames_.pop();
  }

  void key(const std::string& name) override {
    const Frame& f = frames_.keyObject();
    auto it = f.index.find(name);
    if (it == f.index.end()) {
      cur_.reset(f.node);
      fail(Frames::missingField(name, f.keys));
    }
    pending_.reset(f.values[it->second]);
    frames_.select(name);
  }

  bool hasKey(const std::string& name) const override { return frames_.hasKey(name); }

  std::vector<std::string> keys() const override { return frames_.keys(); }

  std::size_t beginArray() override {
    YAML::Node n = slot();
    if (!n.IsSequence()) fail(std::string("expected an array (a sequence), found ") + kindName(n));
    if (frames_.depth() >= kMaxDepth) fail("objects and arrays nested too deep");
    Frame f;
    f.node.reset(n);
    f.object = false;
    for (const auto& e : n) f.values.push_back(static_cast<const YAML::Node&>(e));
    f.count = f.values.size();
    f.segment = frames_.takeSegment();
    frames_.push(std::move(f));
    return frames_.top().count;
  }

  void endArray() override {
    cur_.reset(frames_.closing(false).node);
    frames_.pop();
  }

  bool readBool() override {
    const std::string& s = scalar("a bool");
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
    fail("expected a bool (true or false), found '" + s + "'");
  }

  std::int64_t readInt() override {
    const std::string& s = scalar("an integer");
    return parseInt(s);
  }

  std::uint64_t readUInt() override {
    const std::string& s = scalar("an unsigned integer");
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') ++b;
    std::uint64_t v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec == std::errc::result_out_of_range) fail("integer '" + s + "' is out of range");
    if (r.ec != std::errc() || r.ptr != e || b == e) {
      fail("expected an unsigned integer, found '" + s + "'");
    }
    return v;
  }

  double readDouble() override { return parseDouble(scalar("a double")); }

  std::string readString() override { return scalar("a string"); }

  void readDoubles(const std::function<double*(std::size_t n)>& storage) override {
    YAML::Node n = slot();
    if (!n.IsSequence()) {
      fail(std::string("expected a sequence of numbers, found ") + kindName(n));
    }
    const std::size_t count = n.size();
    double* dst = storage(count);
    std::size_t i = 0;
    for (const auto& it : n) {
      const YAML::Node& e = it;
      cur_.reset(e);
      if (!e.IsScalar()) {
        fail("element " + std::to_string(i) + ": expected a number, found " + kindName(e));
      }
      dst[i++] = parseDouble(e.Scalar());
    }
    cur_.reset(n);
  }

  [[noreturn]] void fail(const std::string& message) const override {
    throw ParseError(source_, lineOf(cur_), "text archive, at " + frames_.path() + ": " + message);
  }

 private:
  struct Frame {
    YAML::Node node;
    bool object = false;
    std::string segment;
    std::vector<std::string> keys;
    std::vector<YAML::Node> values;
    std::unordered_map<std::string, std::size_t> index;
    std::size_t count = 0;
    std::size_t next = 0;
  };

  using Frames = ReaderFrames<Frame>;

  static int lineOf(const YAML::Node& n) {
    if (!n.IsDefined()) return 0;
    const YAML::Mark m = n.Mark();
    return m.is_null() ? 0 : m.line + 1;
  }

  YAML::Node slot() {
    switch (frames_.next()) {
      case Frames::Next::kRoot:
        cur_.reset(root_);
        return root_;
      case Frames::Next::kField:
        cur_.reset(pending_);
        return pending_;
      case Frames::Next::kElement:
        break;
    }
    Frame& f = frames_.top();
    if (const std::string past = frames_.pastEnd(); !past.empty()) {
      cur_.reset(f.node);
      fail(past);
    }
    cur_.reset(f.values[frames_.element()]);
    return cur_;
  }

  const std::string& scalar(const char* expected) {
    YAML::Node n = slot();
    if (!n.IsScalar()) fail(std::string("expected ") + expected + ", found " + kindName(n));
    scalar_ = n.Scalar();
    return scalar_;
  }

  std::int64_t parseInt(const std::string& s) const {
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') ++b;
    std::int64_t v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec == std::errc::result_out_of_range) fail("integer '" + s + "' is out of range");
    if (r.ec != std::errc() || r.ptr != e || b == e) fail("expected an integer, found '" + s + "'");
    return v;
  }

  double parseDouble(const std::string& s) const {
    if (s == ".nan" || s == ".NaN" || s == ".NAN") return std::numeric_limits<double>::quiet_NaN();
    if (s == ".inf" || s == ".Inf" || s == ".INF" || s == "+.inf" || s == "+.Inf" || s == "+.INF") {
      return std::numeric_limits<double>::infinity();
    }
    if (s == "-.inf" || s == "-.Inf" || s == "-.INF")
      return -std::numeric_limits<double>::infinity();
    const char* b = s.data();
    const char* e = b + s.size();
    if (b != e && *b == '+') ++b;
    double v = 0;
    const auto r = std::from_chars(b, e, v);
    if (r.ec != std::errc() || r.ptr != e || b == e) fail("expected a number, found '" + s + "'");
    return v;
  }

  std::string source_;
  YAML::Node root_;
  Frames frames_{"text"};
  YAML::Node pending_;  // the field that key() selected
  // The node errors point at (for the line number). yaml-cpp's Node::operator= writes through
  // to the referenced node, so every member Node is rebound with reset(), never assigned.
  YAML::Node cur_;
  std::string scalar_;
};

}  // namespace

std::unique_ptr<OutArchive> makeTextOut(std::ostream& out) {
  return std::make_unique<TextOut>(out);
}

std::unique_ptr<InArchive> makeTextIn(std::istream& in, const std::string& source) {
  return std::make_unique<TextIn>(in, source);
}

}  // namespace serialization
}  // namespace abi_v1
}  // namespace plugslam
