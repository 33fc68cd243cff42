#include "plugslam/solver/robust_kernel.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
void checkScale(double scale) {
  if (!std::isfinite(scale) || scale <= 0.0) {
    throw InputError("robust kernel scale must be finite and > 0, got " + std::to_string(scale));
  }
}
}  // namespace

RobustKernel::RobustKernel(double scale) : scale_(scale) { checkScale(scale); }

void RobustKernel::setScale(double scale) {
  checkScale(scale);
  scale_ = scale;
}

Eigen::Vector3d HuberKernel::robustify(double s) const {
  const double d2 = scale_ * scale_;
  if (s <= d2) return {s, 1.0, 0.0};
  const double r = std::sqrt(s);
  return {2.0 * r * scale_ - d2, scale_ / r, -0.5 * scale_ / (r * s)};
}

Eigen::Vector3d CauchyKernel::robustify(double s) const {
  const double c2 = scale_ * scale_;
  const double aux = s / c2 + 1.0;
  return {c2 * std::log(aux), 1.0 / aux, -1.0 / (c2 * aux * aux)};
}

Eigen::Vector3d TukeyKernel::robustify(double s) const {
  const double d2 = scale_ * scale_;
  if (s > d2) return {d2 / 3.0, 0.0, 0.0};
  const double aux = 1.0 - s / d2;
  return {d2 * (1.0 - aux * aux * aux) / 3.0, aux * aux, -2.0 * aux / d2};
}

Eigen::Vector3d DcsKernel::robustify(double s) const {
  // DCS scales the information by w^2, w = min(1, 2 phi / (phi + s)).
  const double w = 2.0 * scale_ / (scale_ + s);
  if (w >= 1.0) return {s, 1.0, 0.0};
  return {w * w * s, w * w, 0.0};
}

std::vector<std::string> robustKernelNames() {
  return {"sdk.Huber", "sdk.Cauchy", "sdk.Tukey", "sdk.DCS"};
}

std::unique_ptr<RobustKernel> makeRobustKernel(const std::string& name, double scale) {
  std::string key = name;
  std::transform(key.begin(), key.end(), key.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (key.rfind("sdk.", 0) == 0) key = key.substr(4);
  checkScale(scale);
  if (key == "huber") return std::make_unique<HuberKernel>(scale);
  if (key == "cauchy") return std::make_unique<CauchyKernel>(scale);
  if (key == "tukey") return std::make_unique<TukeyKernel>(scale);
  if (key == "dcs") return std::make_unique<DcsKernel>(scale);
  std::string valid;
  for (const auto& n : robustKernelNames()) valid += (valid.empty() ? "" : ", ") + n;
  throw InputError("unknown robust kernel '" + name + "'; expected one of: " + valid);
}

}  // namespace abi_v1
}  // namespace plugslam
