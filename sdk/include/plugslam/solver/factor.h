#pragma once
// Factors: typed error terms over a fixed list of variables. A concrete factor derives from
// Factor<ErrorDim, Vars...> and implements error(); it may override errorAndJacobians() with
// analytic Jacobians, otherwise central differences through each variable's oplus are used.
#include <Eigen/Core>
#include <array>
#include <memory>
#include <tuple>
#include <utility>

#include "plugslam/solver/robust_kernel.h"
#include "plugslam/solver/variable.h"

namespace plugslam {
inline namespace abi_v1 {

/// Where one Hessian block of a factor lands in the optimizer's column-major storage: column j
/// of the block starts at offset + j * stride. transposed: the factor's (a, b) block is stored as
/// the system's (b, a) block. offset < 0: the block is not part of the system (fixed variable).
struct BlockSlot {
  int offset = -1;          ///< start of the block's first column
  int stride = 0;           ///< distance between consecutive columns of the block
  bool transposed = false;  ///< store the transpose of the factor's block
};

/// Type-erased factor: what the optimizer and the file writers see.
class FactorBase {
 public:
  virtual ~FactorBase() = default;
  /// Dimension of the error vector.
  virtual int errorDim() const = 0;
  /// Number of variables the factor connects.
  virtual int numVariables() const = 0;
  /// The i-th variable.
  virtual Variable* variable(int i) const = 0;
  /// The squared Mahalanobis error e^T Omega e at the current estimates.
  virtual double chi2() const = 0;
  /// The error vector at the current estimates (dynamic size; for tools and tests).
  virtual Eigen::VectorXd errorVector() const = 0;
  /// Error and the factor's Jacobian (columns stacked in variable order), using the factor's own
  /// Jacobian (analytic, or numeric when the factor does not provide one).
  virtual void evaluate(Eigen::VectorXd& error, Eigen::MatrixXd& jacobian) const = 0;
  /// Error and the Jacobian by central differences with step h (for checks).
  virtual void evaluateNumeric(Eigen::VectorXd& error, Eigen::MatrixXd& jacobian,
                               double h) const = 0;
  /// Accumulates this factor's weighted normal equations: H blocks through slots (one per
  /// pair a <= b, in order (0,0), (0,1), ..., (1,1), ...), b through bOffsets (one per variable,
  /// -1 if fixed) as b += J^T W e. Returns the robust cost rho(chi2). Used by the optimizer.
  virtual double linearize(double* H, double* b, const BlockSlot* slots,
                           const int* bOffsets) const = 0;

  /// rho(chi2()) with the robust kernel, chi2() without one.
  double robustChi2() const {
    const double c = chi2();
    return kernel_ ? kernel_->robustify(c)[0] : c;
  }
  /// Sets (or clears, with nullptr) the robust kernel; kernels may be shared between factors.
  void setRobustKernel(std::shared_ptr<const RobustKernel> kernel) { kernel_ = std::move(kernel); }
  /// The robust kernel, or nullptr.
  const RobustKernel* robustKernel() const { return kernel_.get(); }

 protected:
  std::shared_ptr<const RobustKernel> kernel_;
};

/// A factor with an E-dimensional error over variables of types Vars... (each a VariableT).
template <int E, class... Vars>
class Factor : public FactorBase {
 public:
  /// Error dimension.
  static constexpr int kErrorDim = E;
  /// Number of variables.
  static constexpr int kNumVars = sizeof...(Vars);
  /// Sum of the variables' minimal dimensions.
  static constexpr int kTotalDim = (Vars::kDim + ...);
  /// Minimal dimension of each variable.
  static constexpr std::array<int, kNumVars> kDims = {Vars::kDim...};
  /// Column offset of each variable's block in the stacked Jacobian.
  static constexpr std::array<int, kNumVars> kOffsets = [] {
    std::array<int, kNumVars> o{};
    int acc = 0;
    for (int i = 0; i < kNumVars; ++i) {
      o[i] = acc;
      acc += kDims[i];
    }
    return o;
  }();
  /// The error vector.
  using ErrorVector = Eigen::Matrix<double, E, 1>;
  /// The information matrix (inverse covariance of the error).
  using InformationMatrix = Eigen::Matrix<double, E, E>;
  /// Jacobian of the error w.r.t. all variables, columns stacked in variable order.
  using JacobianMatrix = Eigen::Matrix<double, E, kTotalDim>;

  /// A factor over the given variables with identity information.
  explicit Factor(Vars*... vars) : vars_(vars...), information_(InformationMatrix::Identity()) {}

  /// The error at the current estimates.
  virtual ErrorVector error() const = 0;
  /// Error and Jacobian; the default differentiates error() numerically.
  virtual void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const {
    e = error();
    numericJacobian(J, 1e-6);
  }

  /// The information matrix.
  const InformationMatrix& information() const { return information_; }
  /// Sets the information matrix (symmetric; positive definite for a well-posed problem).
  void setInformation(const InformationMatrix& information) { information_ = information; }
  /// The I-th variable, typed.
  template <int I>
  auto* var() const {
    return std::get<I>(vars_);
  }

  int errorDim() const override { return E; }
  int numVariables() const override { return kNumVars; }
  Variable* variable(int i) const override { return variables()[i]; }
  double chi2() const override {
    const ErrorVector e = error();
    return e.dot(information_ * e);
  }
  Eigen::VectorXd errorVector() const override { return error(); }
  void evaluate(Eigen::VectorXd& error, Eigen::MatrixXd& jacobian) const override {
    ErrorVector e;
    JacobianMatrix J;
    errorAndJacobian(e, J);
    error = e;
    jacobian = J;
  }
  void evaluateNumeric(Eigen::VectorXd& error, Eigen::MatrixXd& jacobian, double h) const override {
    JacobianMatrix J;
    numericJacobian(J, h);
    error = this->error();
    jacobian = J;
  }

  double linearize(double* H, double* b, const BlockSlot* slots,
                   const int* bOffsets) const override {
    ErrorVector e;
    JacobianMatrix J;
    errorAndJacobian(e, J);
    const ErrorVector oe = information_ * e;
    const double c = e.dot(oe);
    double weight = 1.0, cost = c;
    if (kernel_) {
      const Eigen::Vector3d rho = kernel_->robustify(c);
      cost = rho[0];
      weight = rho[1];
    }
    const Eigen::Matrix<double, kTotalDim, E> JtW = weight * (J.transpose() * information_);
    const Eigen::Matrix<double, kTotalDim, 1> g = weight * (J.transpose() * oe);
    const Eigen::Matrix<double, kTotalDim, kTotalDim> Hf = JtW * J;
    int slot = 0;
    for (int a = 0; a < kNumVars; ++a) {
      if (bOffsets[a] >= 0) {
        double* ba = b + bOffsets[a];
        for (int r = 0; r < kDims[a]; ++r) ba[r] += g[kOffsets[a] + r];
      }
      for (int c2 = a; c2 < kNumVars; ++c2, ++slot) {
        const BlockSlot& s = slots[slot];
        if (s.offset < 0) continue;
        double* base = H + s.offset;
        if (!s.transposed) {
          for (int j = 0; j < kDims[c2]; ++j) {
            double* col = base + j * s.stride;
            for (int i = 0; i < kDims[a]; ++i) col[i] += Hf(kOffsets[a] + i, kOffsets[c2] + j);
          }
        } else {
          for (int j = 0; j < kDims[a]; ++j) {
            double* col = base + j * s.stride;
            for (int i = 0; i < kDims[c2]; ++i) col[i] += Hf(kOffsets[c2] + i, kOffsets[a] + j);
          }
        }
      }
    }
    return cost;
  }

  /// Central-difference Jacobian of error() with step h along each tangent direction.
  void numericJacobian(JacobianMatrix& J, double h) const {
    numericBlocks(J, h, std::index_sequence_for<Vars...>{});
  }

 protected:
  /// The variables, typed.
  std::tuple<Vars*...> vars_;
  /// The information matrix.
  InformationMatrix information_;

 private:
  std::array<Variable*, kNumVars> variables() const {
    return std::apply([](auto*... v) { return std::array<Variable*, kNumVars>{v...}; }, vars_);
  }

  template <size_t... Is>
  void numericBlocks(JacobianMatrix& J, double h, std::index_sequence<Is...>) const {
    (numericBlock<Is>(J, h), ...);
  }

  template <size_t I>
  void numericBlock(JacobianMatrix& J, double h) const {
    auto* v = std::get<I>(vars_);
    using V = std::remove_pointer_t<decltype(v)>;
    const typename V::Estimate x0 = v->estimate();
    for (int k = 0; k < V::kDim; ++k) {
      double d[V::kDim] = {};
      d[k] = h;
      v->setEstimate(V::oplusTo(x0, d));
      const ErrorVector ep = error();
      d[k] = -h;
      v->setEstimate(V::oplusTo(x0, d));
      const ErrorVector em = error();
      J.col(kOffsets[I] + k) = (ep - em) / (2.0 * h);
    }
    v->setEstimate(x0);
  }
};

}  // namespace abi_v1
}  // namespace plugslam
