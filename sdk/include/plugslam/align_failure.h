#pragma once
// Why an alignment (or a tracked frame) did not give a valid pose: each tracking failure names
// its reason in the debug log, run.json and the end-of-run summary (issue 20).
#include <cstddef>

namespace plugslam {
inline namespace abi_v1 {

/// The reason an alignment is not valid; `none` when it is.
enum class AlignFailure {
  none = 0,
  no_data,          ///< no cue gave a factor (an empty or absent measurement or scene)
  too_few_inliers,  ///< fewer inlier factors than the aligner's min_inliers
  degenerate,       ///< the information is rank deficient: some direction is unconstrained
  slid,             ///< the solve left the searched pose by a distinct peak's distance
                    ///< (MultiAligner::distinct)
};

/// Number of AlignFailure values (for counters indexed by reason).
constexpr std::size_t kAlignFailures = 5;

/// "none", "no_data", "too_few_inliers", "degenerate", "slid": run.json's keys.
const char* toString(AlignFailure failure);

}  // namespace abi_v1
}  // namespace plugslam
