#pragma once
// The nesting bookkeeping both archive readers share, so a misuse (a read without a key, a
// second root, an end without a begin) is refused the same way whatever the format, and every
// message names the value it is about by the same path ('pose.data[3]').
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {
namespace serialization {

/// The open objects and arrays of an InArchive and the value the next read takes. `Frame` is the
/// reader's own record of one open object or array, with at least `object`, `segment`, `keys`,
/// `index` (name to the reader's handle on the field), `count` and `next`.
template <class Frame>
class ReaderFrames {
 public:
  /// Which value the next read takes.
  enum class Next { kRoot, kField, kElement };

  /// `backend` names the format in misuse messages ("binary", "text").
  explicit ReaderFrames(const char* backend) : backend_(backend) {}

  [[noreturn]] void misuse(const std::string& what) const {
    throw std::logic_error(std::string("InArchive (") + backend_ + "): " + what);
  }

  /// How many objects and arrays are open.
  int depth() const { return static_cast<int>(frames_.size()); }
  /// The innermost open object or array.
  Frame& top() { return frames_.back(); }

  bool hasKey(const std::string& name) const {
    if (frames_.empty() || !frames_.back().object) return false;
    return frames_.back().index.count(name) > 0;
  }

  const std::vector<std::string>& keys() const {
    if (frames_.empty() || !frames_.back().object) misuse("keys() outside an object");
    return frames_.back().keys;
  }

  /// For key(): the innermost object, one of whose fields select() then makes the next read.
  const Frame& keyObject() {
    if (frames_.empty() || !frames_.back().object) misuse("key() outside an object");
    seg_.clear();
    return frames_.back();
  }
  /// Makes field `name` of the innermost object the next read.
  void select(const std::string& name) {
    pending_key_ = name;
    has_pending_ = true;
  }

  /// The path segment of the value that opens an object or array, for its Frame; taken before
  /// the reader looks into the value, so that messages about its content name where it stands.
  std::string takeSegment() {
    std::string s = std::move(seg_);
    seg_.clear();
    return s;
  }
  void push(Frame f) { frames_.push_back(std::move(f)); }

  /// The innermost frame, which endObject() (`object`) or endArray() is about to close.
  Frame& closing(bool object) {
    if (frames_.empty() || frames_.back().object != object)
      misuse(object ? "endObject() without beginObject()" : "endArray() without beginArray()");
    return frames_.back();
  }
  void pop() {
    seg_.clear();
    has_pending_ = false;
    frames_.pop_back();
  }

  /// Checks that a read may come now and says which value it takes; for an element, call
  /// pastEnd() and then element().
  Next next() {
    if (frames_.empty()) {
      if (root_taken_) misuse("the archive holds one root value, already read");
      root_taken_ = true;
      seg_.clear();
      return Next::kRoot;
    }
    if (frames_.back().object) {
      if (!has_pending_) misuse("a read inside an object needs key() first");
      has_pending_ = false;
      seg_ = "." + pending_key_;
      return Next::kField;
    }
    return Next::kElement;
  }
  /// Why the innermost array has no element left to read; empty when it has.
  std::string pastEnd() const {
    const Frame& f = frames_.back();
    if (f.next < f.count) return "";
    return "read past the end of an array of " + std::to_string(f.count) + " elements";
  }
  /// The index of the innermost array's element the read takes, counted as read.
  std::size_t element() {
    Frame& f = frames_.back();
    seg_ = "[" + std::to_string(f.next) + "]";
    return f.next++;
  }

  /// Where the value being read stands, for messages: "the root" or 'pose.data[3]'.
  std::string path() const {
    std::string p;
    for (const auto& f : frames_) p += f.segment;
    p += seg_;
    if (!p.empty() && p[0] == '.') p.erase(0, 1);
    return p.empty() ? "the root" : "'" + p + "'";
  }

  /// The message for a field `name` that the object with `keys` does not have.
  static std::string missingField(const std::string& name, const std::vector<std::string>& keys) {
    std::string have;
    for (const auto& k : keys) have += (have.empty() ? "" : ", ") + k;
    return "missing field '" + name + "'" +
           (have.empty() ? std::string(" (the object is empty)")
                         : " (fields present: " + have + ")");
  }

 private:
  const char* backend_;
  std::vector<Frame> frames_;
  std::string seg_;
  bool has_pending_ = false;
  std::string pending_key_;
  bool root_taken_ = false;
};

}  // namespace serialization
}  // namespace abi_v1
}  // namespace plugslam
