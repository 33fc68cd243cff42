#pragma once
// Per-module wall-time accounting for run.json and the progress line.
#include <chrono>
#include <string>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

/// Accumulated time of one module.
struct TimingEntry {
  std::string module;
  double total_s = 0;
  uint64_t calls = 0;
};

/// Accumulates wall time per module name, in first-seen order.
class Timings {
 public:
  /// Adds one call of `seconds` to `module`.
  void add(const std::string& module, double seconds);
  /// Every module seen so far.
  const std::vector<TimingEntry>& entries() const { return entries_; }
  /// Forgets everything.
  void clear() { entries_.clear(); }

 private:
  std::vector<TimingEntry> entries_;
};

/// Measures the lifetime of a scope into a Timings entry.
class ScopedTimer {
 public:
  ScopedTimer(Timings& timings, const std::string& module)
      : timings_(timings), module_(module), start_(std::chrono::steady_clock::now()) {}
  ~ScopedTimer() {
    timings_.add(module_,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  }
  ScopedTimer(const ScopedTimer&) = delete;
  ScopedTimer& operator=(const ScopedTimer&) = delete;

 private:
  Timings& timings_;
  const std::string& module_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace abi_v1
}  // namespace plugslam
