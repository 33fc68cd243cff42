#pragma once
// The nesting bookkeeping both archive writers share, so a misuse (a value without a key, an
// array shorter than announced, a second root) is caught the same way whatever the format.
#include <cstddef>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {
namespace serialization {

/// The open objects and arrays of an OutArchive and the calls each allows next.
class WriterFrames {
 public:
  /// One open object or array.
  struct Frame {
    bool object = false;
    bool key_pending = false;
    std::size_t count = 0;
    std::size_t expected = 0;
    std::size_t patch_pos = 0;  // where a writer that patches the count later keeps it
    std::unordered_set<std::string> keys;
  };

  /// `backend` names the format in misuse messages ("binary", "text").
  explicit WriterFrames(const char* backend) : backend_(backend) {}

  [[noreturn]] void misuse(const std::string& what) const {
    throw std::logic_error(std::string("OutArchive (") + backend_ + "): " + what);
  }

  /// Checks that a value may stand here and counts it.
  void beforeValue() {
    if (finished_) misuse("write after finish()");
    if (frames_.empty()) {
      if (root_written_) misuse("an archive holds one root value; wrap several in an object");
      root_written_ = true;
      return;
    }
    Frame& f = frames_.back();
    if (f.object) {
      if (!f.key_pending) misuse("a value inside an object needs key() first");
      f.key_pending = false;
    } else if (f.count >= f.expected) {
      misuse("more array elements than the " + std::to_string(f.expected) + " announced");
    }
    ++f.count;
  }

  /// Opens an object (after beforeValue()).
  Frame& openObject() {
    Frame f;
    f.object = true;
    frames_.push_back(std::move(f));
    return frames_.back();
  }

  /// Opens an array of `size` elements (after beforeValue()).
  void openArray(std::size_t size) {
    Frame f;
    f.expected = size;
    frames_.push_back(std::move(f));
  }

  /// Checks a key; the writer sets key_pending once it has written the key.
  Frame& acceptKey(const std::string& name) {
    if (frames_.empty() || !frames_.back().object) misuse("key() outside an object");
    Frame& f = frames_.back();
    if (f.key_pending) misuse("two key() calls without a value");
    if (!f.keys.insert(name).second) misuse("duplicate field '" + name + "'");
    return f;
  }

  /// Closes the innermost object and hands it back (its count, its patch position).
  Frame closeObject() {
    Frame& f = top("endObject");
    if (!f.object) misuse("endObject() closes an array");
    if (f.key_pending) misuse("key() without a value before endObject()");
    return pop();
  }

  /// Closes the innermost array, which must hold as many elements as announced.
  void closeArray() {
    Frame& f = top("endArray");
    if (f.object) misuse("endArray() closes an object");
    if (f.count != f.expected) {
      misuse("array announced " + std::to_string(f.expected) + " elements, got " +
             std::to_string(f.count));
    }
    pop();
  }

  /// Checks that the archive holds one complete root value and may be finished.
  void checkFinish() const {
    if (finished_) misuse("finish() called twice");
    if (!frames_.empty()) misuse("finish() with an unclosed object or array");
    if (!root_written_) misuse("finish() before any value was written");
  }

  void markFinished() { finished_ = true; }

 private:
  Frame& top(const char* call) {
    if (frames_.empty()) misuse(std::string(call) + "() with nothing open");
    return frames_.back();
  }

  Frame pop() {
    Frame f = std::move(frames_.back());
    frames_.pop_back();
    return f;
  }

  const char* backend_;
  std::vector<Frame> frames_;
  bool root_written_ = false;
  bool finished_ = false;
};

}  // namespace serialization
}  // namespace abi_v1
}  // namespace plugslam
