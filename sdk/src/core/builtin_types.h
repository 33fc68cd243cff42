#pragma once
// The SDK's own configurable types, registered as "sdk.<Type>" when the registry is first used.
#include "plugslam/registry.h"

namespace plugslam {
inline namespace abi_v1 {
/// Registers every built-in type.
void registerBuiltinTypes(Registrar& registrar);
}  // namespace abi_v1
}  // namespace plugslam
