#include "sweep/case_id.h"

#include <fmt/format.h>

#include <cstdint>

namespace plugslam::runtime::sweep {

namespace {

// FNV-1a: fixed by its definition, so ids never change with the compiler or the library.
struct Fnv1a {
  uint64_t h = 14695981039346656037ull;
  void add(const std::string& s) {
    const std::string prefix = std::to_string(s.size()) + ":";
    for (unsigned char c : prefix) h = (h ^ c) * 1099511628211ull;
    for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  }
};

}  // namespace

std::string caseId(const std::string& config_text, const std::vector<std::string>& overrides,
                   int repeat) {
  Fnv1a f;
  f.add("plugslam-sweep-case-1");
  f.add(config_text);
  for (const auto& o : overrides) f.add(o);
  f.add(std::to_string(repeat));
  return fmt::format("{:016x}", f.h);
}

}  // namespace plugslam::runtime::sweep
