#include "plugslam/timings.h"

namespace plugslam {
inline namespace abi_v1 {
void Timings::add(const std::string& module, double seconds) {
  for (auto& e : entries_) {
    if (e.module == module) {
      e.total_s += seconds;
      ++e.calls;
      return;
    }
  }
  entries_.push_back(TimingEntry{module, seconds, 1});
}
}  // namespace abi_v1
}  // namespace plugslam
