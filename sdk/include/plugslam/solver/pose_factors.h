#pragma once
// Pose-graph factors. Errors follow g2o's EdgeSE2 / EdgeSE3 exactly so chi2 values compare:
// SE2: toVector(Z^-1 Xi^-1 Xj) with the angle wrapped; SE3: (t, q.vec) of Z^-1 Xi^-1 Xj, q.w >= 0.
#include "plugslam/solver/factor.h"

namespace plugslam {
inline namespace abi_v1 {

/// What every pose factor keeps of its measurement Z: Z, and Z^-1, with which each error starts.
template <class Pose, int E, class... Vars>
class PoseMeasurementFactor : public Factor<E, Vars...> {
 public:
  /// The measured pose: Xi^-1 Xj for a between factor, X for a prior.
  const Pose& measurement() const { return measurement_; }

 protected:
  PoseMeasurementFactor(Vars*... vars, const Pose& measurement,
                        const typename Factor<E, Vars...>::InformationMatrix& information)
      : Factor<E, Vars...>(vars...),
        measurement_(measurement),
        inverse_measurement_(measurement.inverse()) {
    this->setInformation(information);
  }

  Pose measurement_;
  Pose inverse_measurement_;
};

/// Relative planar pose measurement Z between Xi and Xj.
class BetweenFactorSE2 final : public PoseMeasurementFactor<SE2, 3, VariableSE2, VariableSE2> {
 public:
  /// Measurement Z of Xi^-1 Xj with the given information.
  BetweenFactorSE2(VariableSE2* xi, VariableSE2* xj, const SE2& measurement,
                   const Eigen::Matrix3d& information = Eigen::Matrix3d::Identity());
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  double measurement_angle_;
};

/// Relative 3D pose measurement Z between Xi and Xj.
class BetweenFactorSE3 final : public PoseMeasurementFactor<SE3, 6, VariableSE3, VariableSE3> {
 public:
  /// Measurement Z of Xi^-1 Xj with the given information (error order: t, q.vec).
  BetweenFactorSE3(
      VariableSE3* xi, VariableSE3* xj, const SE3& measurement,
      const Eigen::Matrix<double, 6, 6>& information = Eigen::Matrix<double, 6, 6>::Identity());
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;
};

/// Absolute planar pose prior Z on X: error toVector(Z^-1 X).
class PriorFactorSE2 final : public PoseMeasurementFactor<SE2, 3, VariableSE2> {
 public:
  /// Prior Z with the given information.
  PriorFactorSE2(VariableSE2* x, const SE2& measurement,
                 const Eigen::Matrix3d& information = Eigen::Matrix3d::Identity());
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;

 private:
  double measurement_angle_;
};

/// Absolute 3D pose prior Z on X: error (t, q.vec) of Z^-1 X.
class PriorFactorSE3 final : public PoseMeasurementFactor<SE3, 6, VariableSE3> {
 public:
  /// Prior Z with the given information.
  PriorFactorSE3(
      VariableSE3* x, const SE3& measurement,
      const Eigen::Matrix<double, 6, 6>& information = Eigen::Matrix<double, 6, 6>::Identity());
  ErrorVector error() const override;
  void errorAndJacobian(ErrorVector& e, JacobianMatrix& J) const override;
};

}  // namespace abi_v1
}  // namespace plugslam
