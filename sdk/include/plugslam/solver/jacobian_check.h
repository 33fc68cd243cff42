#pragma once
// Test helper: compares a factor's own Jacobian (analytic, or its fallback) with central
// differences at the variables' current estimates. Usable from any plugin test:
//   auto r = plugslam::checkJacobian(factor);
//   EXPECT_TRUE(r.ok) << r;
#include <ostream>
#include <string>
#include <vector>

#include "plugslam/solver/factor.h"

namespace plugslam {
inline namespace abi_v1 {

/// Result of checkJacobian: per variable block, the largest absolute difference.
struct JacobianCheckResult {
  bool ok = true;                     ///< every block within tolerance
  std::vector<double> max_abs_error;  ///< one per variable, in factor order
  std::vector<double> max_abs_value;  ///< largest |entry| of each numeric block (scale)
  double tolerance = 0.0;             ///< the absolute tolerance used (after scaling)
  std::string describe() const;       ///< a one-line summary for test failure messages
  /// Truthy when ok, so EXPECT_TRUE(checkJacobian(f)) works.
  explicit operator bool() const { return ok; }
};

/// Prints describe().
inline std::ostream& operator<<(std::ostream& os, const JacobianCheckResult& r) {
  return os << r.describe();
}

/// Checks the factor's Jacobian against central differences with step h. A block passes when
/// max |J - Jnum| <= tolerance * max(1, max |Jnum|).
JacobianCheckResult checkJacobian(const FactorBase& factor, double tolerance = 1e-6,
                                  double h = 1e-6);

}  // namespace abi_v1
}  // namespace plugslam
