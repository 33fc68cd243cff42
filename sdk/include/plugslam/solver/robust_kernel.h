#pragma once
// Robust kernels rho(s) of the squared Mahalanobis error s = e^T Omega e. The optimizer uses
// iteratively reweighted least squares: the factor's information is scaled by rho'(s).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

/// A robust kernel with a scale parameter (in units of the error, not squared).
class RobustKernel {
 public:
  /// A kernel with scale delta > 0.
  explicit RobustKernel(double scale);
  virtual ~RobustKernel() = default;
  /// (rho(s), rho'(s), rho''(s)) at squared error s >= 0.
  virtual Eigen::Vector3d robustify(double s) const = 0;
  /// The kernel's registry name, e.g. "sdk.Huber".
  virtual const char* name() const = 0;
  /// The scale parameter delta.
  double scale() const { return scale_; }
  /// Changes the scale parameter; throws InputError unless finite and > 0.
  void setScale(double scale);

 protected:
  double scale_;
};

/// Huber: quadratic within delta, linear beyond.
class HuberKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double s) const override;
  const char* name() const override { return "sdk.Huber"; }
};

/// Cauchy (Lorentzian): delta^2 log(1 + s / delta^2).
class CauchyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double s) const override;
  const char* name() const override { return "sdk.Cauchy"; }
};

/// Tukey biweight: redescending, zero weight beyond delta.
class TukeyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double s) const override;
  const char* name() const override { return "sdk.Tukey"; }
};

/// Dynamic covariance scaling (Agarwal et al. 2013), phi = scale.
class DcsKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  Eigen::Vector3d robustify(double s) const override;
  const char* name() const override { return "sdk.DCS"; }
};

/// The names makeRobustKernel accepts (with the "sdk." prefix).
std::vector<std::string> robustKernelNames();

/// Builds a kernel by name ("Huber" or "sdk.Huber", case-insensitive); throws InputError listing
/// the valid names for an unknown one, or for a scale that is not finite and positive.
std::unique_ptr<RobustKernel> makeRobustKernel(const std::string& name, double scale);

}  // namespace abi_v1
}  // namespace plugslam
