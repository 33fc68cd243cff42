#include "plugslam/plugin.h"

namespace plugslam {
inline namespace abi_v1 {
// Compiled into the SDK with the host's flags: what every plugin must match.
const char* hostBuildFingerprint() { return PLUGSLAM_BUILD_FINGERPRINT; }
}  // namespace abi_v1
}  // namespace plugslam
