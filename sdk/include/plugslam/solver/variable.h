#pragma once
// Optimisation variables on their manifolds. Every variable is updated by a right perturbation
// x <- x (+) delta of its minimal dimension; poses use the decoupled retraction
// t <- t + R * rho, R <- R * Exp(phi), which is what g2o's SE3 vertex does too.
#include <cstdint>

#include "plugslam/geometry.h"

namespace plugslam {
inline namespace abi_v1 {

/// Base of every optimisation variable: id, minimal dimension, fixed flag and oplus.
class Variable {
 public:
  /// A variable with a user id (unique in its graph) and a minimal dimension.
  Variable(int64_t id, int dim) : id_(id), dim_(dim) {}
  virtual ~Variable() = default;
  Variable(const Variable&) = delete;
  Variable& operator=(const Variable&) = delete;

  /// The user id of this variable.
  int64_t id() const { return id_; }
  /// The minimal (tangent) dimension.
  int dim() const { return dim_; }
  /// A fixed variable is never updated by the optimizer (it also fixes the gauge).
  bool fixed() const { return fixed_; }
  /// Fixes or frees the variable.
  void setFixed(bool fixed) { fixed_ = fixed; }
  /// Applies x <- x (+) delta, delta has dim() entries.
  virtual void oplus(const double* delta) = 0;
  /// Saves the current estimate in the one backup slot (LM uses it to reject a step).
  virtual void saveEstimate() = 0;
  /// Restores the estimate saved by saveEstimate().
  virtual void restoreEstimate() = 0;
  /// A short type name ("SE2", "SE3", "Point2", "Point3").
  virtual const char* typeName() const = 0;

  /// Scalar offset of this variable in the optimizer's linear system, -1 when not optimised.
  /// Set by the optimizer; not meaningful outside an optimize() call.
  int systemOffset() const { return system_offset_; }
  /// Used by the optimizer only.
  void setSystemOffset(int offset) { system_offset_ = offset; }

 private:
  int64_t id_;
  int dim_;
  bool fixed_ = false;
  int system_offset_ = -1;
};

/// A variable of minimal dimension D whose estimate has type T.
template <int D, class T>
class VariableT : public Variable {
 public:
  /// Minimal dimension, known at compile time.
  static constexpr int kDim = D;
  /// Type of the estimate.
  using Estimate = T;
  /// A tangent vector.
  using Delta = Eigen::Matrix<double, D, 1>;

  /// A variable with id and initial estimate.
  VariableT(int64_t id, const T& estimate)
      : Variable(id, D), estimate_(estimate), backup_(estimate) {}
  /// The current estimate.
  const T& estimate() const { return estimate_; }
  /// Replaces the current estimate.
  void setEstimate(const T& estimate) { estimate_ = estimate; }
  void saveEstimate() override { backup_ = estimate_; }
  void restoreEstimate() override { estimate_ = backup_; }
  /// Applies oplus to an estimate without touching the variable (numeric differentiation).
  static T oplusTo(const T& x, const double* delta);
  void oplus(const double* delta) override { estimate_ = oplusTo(estimate_, delta); }

 protected:
  T estimate_;
  T backup_;
};

/// A planar pose; perturbation (rho_x, rho_y, phi) applied on the right.
class VariableSE2 final : public VariableT<3, SE2> {
 public:
  using VariableT::VariableT;
  const char* typeName() const override { return "SE2"; }
};

/// A 3D pose; perturbation (rho, phi) in R^6 applied on the right.
class VariableSE3 final : public VariableT<6, SE3> {
 public:
  using VariableT::VariableT;
  const char* typeName() const override { return "SE3"; }
};

/// A 2D point; additive update.
class VariablePoint2 final : public VariableT<2, Eigen::Vector2d> {
 public:
  using VariableT::VariableT;
  const char* typeName() const override { return "Point2"; }
};

/// A 3D point; additive update.
class VariablePoint3 final : public VariableT<3, Eigen::Vector3d> {
 public:
  using VariableT::VariableT;
  const char* typeName() const override { return "Point3"; }
};

template <>
inline SE2 VariableT<3, SE2>::oplusTo(const SE2& x, const double* d) {
  SE2 r;
  r.translation() = x.translation() + x.linear() * Eigen::Vector2d(d[0], d[1]);
  // Rebuilding R from the angle keeps it exactly orthonormal.
  r.linear() = rotation2(angleOf(x.linear()) + d[2]);
  r.makeAffine();
  return r;
}

template <>
inline SE3 VariableT<6, SE3>::oplusTo(const SE3& x, const double* d) {
  SE3 r;
  r.translation() = x.translation() + x.linear() * Eigen::Vector3d(d[0], d[1], d[2]);
  const Eigen::Quaterniond q = (Eigen::Quaterniond(x.linear()) *
                                Eigen::Quaterniond(so3Exp(Eigen::Vector3d(d[3], d[4], d[5]))))
                                   .normalized();
  r.linear() = q.toRotationMatrix();
  r.makeAffine();
  return r;
}

template <>
inline Eigen::Vector2d VariableT<2, Eigen::Vector2d>::oplusTo(const Eigen::Vector2d& x,
                                                              const double* d) {
  return x + Eigen::Vector2d(d[0], d[1]);
}

template <>
inline Eigen::Vector3d VariableT<3, Eigen::Vector3d>::oplusTo(const Eigen::Vector3d& x,
                                                              const double* d) {
  return x + Eigen::Vector3d(d[0], d[1], d[2]);
}

/// A typed handle to a variable of a graph: FactorGraph::get(VariableId<V>) returns a V&.
template <class V>
struct VariableId {
  int64_t value;  ///< the variable's user id
};

}  // namespace abi_v1
}  // namespace plugslam
