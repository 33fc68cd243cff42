// Out-of-line destructors of the loop-closure interfaces (they anchor the vtables in the SDK).
#include "plugslam/loop_closure.h"

namespace plugslam {
inline namespace abi_v1 {
LoopDetector::~LoopDetector() = default;
LoopValidator::~LoopValidator() = default;
}  // namespace abi_v1
}  // namespace plugslam
