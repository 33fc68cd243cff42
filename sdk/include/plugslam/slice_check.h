#pragma once
// Test helper: runs the SDK's Jacobian check (solver/jacobian_check.h) on every factor an aligner
// slice adds, so a slice's test covers its factors as a graph factor's test does:
//   ASSERT_TRUE(slice.bind(frame, scene, context));
//   slice.associate(t);
//   const SliceJacobianCheck r = checkSliceJacobians(slice, t);
//   EXPECT_GT(r.factors, 0u);
//   EXPECT_TRUE(r.ok()) << r;
#include <cstddef>
#include <ostream>
#include <string>

#include "plugslam/aligner_slice.h"
#include "plugslam/solver/jacobian_check.h"

namespace plugslam {
inline namespace abi_v1 {

/// Result of checkSliceJacobians.
struct SliceJacobianCheck {
  size_t factors = 0;         ///< factors the slice added
  size_t failed = 0;          ///< of them, those whose Jacobian is outside the tolerance
  JacobianCheckResult worst;  ///< the check of the factor furthest from its numeric Jacobian
  /// Every factor passed (and there was at least one).
  bool ok() const { return factors > 0 && failed == 0; }
  /// A one-line summary for test failure messages.
  std::string describe() const;
};

/// Prints describe().
inline std::ostream& operator<<(std::ostream& os, const SliceJacobianCheck& r) {
  return os << r.describe();
}

/// Linearizes the bound slice at t and runs checkJacobian(factor, tolerance, h) on each factor it
/// adds (central differences through the pose variable's oplus, the aligner's boxplus).
template <class S>
SliceJacobianCheck checkSliceJacobians(const AlignerSlice<S>& slice, const typename S::Pose& t,
                                       double tolerance = 1e-6, double h = 1e-6);

extern template SliceJacobianCheck checkSliceJacobians<Space2D>(const AlignerSlice<Space2D>&,
                                                                const Space2D::Pose&, double,
                                                                double);
extern template SliceJacobianCheck checkSliceJacobians<Space3D>(const AlignerSlice<Space3D>&,
                                                                const Space3D::Pose&, double,
                                                                double);

}  // namespace abi_v1
}  // namespace plugslam
