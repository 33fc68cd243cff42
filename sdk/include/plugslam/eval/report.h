#pragma once
// Markdown and JSON renderings of evaluation results, for `plugslam eval` and the benchmarks.
#include <string>

#include "plugslam/eval/ate.h"
#include "plugslam/eval/crispness.h"
#include "plugslam/eval/relations.h"
#include "plugslam/eval/rpe.h"

namespace plugslam {
inline namespace abi_v1 {

/// A markdown table of the ATE statistics.
std::string toMarkdown(const AteResult& result);
/// A markdown table of the RPE statistics.
std::string toMarkdown(const RpeResult& result);
/// A markdown table of the relation-metric errors (mean ± std).
std::string toMarkdown(const RelationResult& result);
/// A markdown table of the crispness result.
std::string toMarkdown(const CrispnessResult& result);

/// One JSON object with the ATE statistics (no per-pose errors); non-finite numbers are null.
std::string toJson(const AteResult& result);
/// One JSON object with the RPE statistics.
std::string toJson(const RpeResult& result);
/// One JSON object with the relation-metric errors.
std::string toJson(const RelationResult& result);
/// One JSON object with the crispness result.
std::string toJson(const CrispnessResult& result);

}  // namespace abi_v1
}  // namespace plugslam
