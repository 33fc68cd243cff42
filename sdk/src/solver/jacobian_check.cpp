#include "plugslam/solver/jacobian_check.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace plugslam {
inline namespace abi_v1 {

std::string JacobianCheckResult::describe() const {
  std::ostringstream os;
  os << (ok ? "jacobian ok" : "jacobian MISMATCH") << " (tolerance " << tolerance << "):";
  for (size_t i = 0; i < max_abs_error.size(); ++i) {
    os << " block " << i << " max abs error " << max_abs_error[i] << " (scale " << max_abs_value[i]
       << ")";
  }
  return os.str();
}

JacobianCheckResult checkJacobian(const FactorBase& factor, double tolerance, double h) {
  JacobianCheckResult r;
  r.tolerance = tolerance;
  Eigen::VectorXd e, en;
  Eigen::MatrixXd j, jn;
  factor.evaluate(e, j);
  factor.evaluateNumeric(en, jn, h);
  int col = 0;
  for (int v = 0; v < factor.numVariables(); ++v) {
    const int d = factor.variable(v)->dim();
    const double diff = (j.middleCols(col, d) - jn.middleCols(col, d)).cwiseAbs().maxCoeff();
    const double scale = jn.middleCols(col, d).cwiseAbs().maxCoeff();
    r.max_abs_error.push_back(diff);
    r.max_abs_value.push_back(scale);
    if (!(diff <= tolerance * std::max(1.0, scale))) r.ok = false;
    col += d;
  }
  if (!((e - en).cwiseAbs().maxCoeff() <= 1e-12 * std::max(1.0, en.cwiseAbs().maxCoeff()))) {
    r.ok = false;  // errorAndJacobian() disagrees with error()
  }
  return r;
}

}  // namespace abi_v1
}  // namespace plugslam
