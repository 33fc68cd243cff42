#pragma once
// A case's id is a hash of everything that decides its result: the config's resolved text, the
// overrides in the order they are applied, and the repeat number. The same case planned again,
// in any folder, on any machine, gets the same id, so its finished result is found and kept.
#include <string>
#include <vector>

namespace plugslam::runtime::sweep {

/// 16 hex digits (64-bit FNV-1a over the parts, each length-prefixed so no two lists of parts
/// hash the same text).
std::string caseId(const std::string& config_text, const std::vector<std::string>& overrides,
                   int repeat);

}  // namespace plugslam::runtime::sweep
