#include "plugslam/eval/ate.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include "core/enum_names.h"
#include "eval/text_file.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;

double rotationAngle(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle(); }
}  // namespace

namespace {
constexpr EnumName<Alignment> kAlignmentNames[] = {{Alignment::None, "none"},
                                                   {Alignment::SE2, "se2"},
                                                   {Alignment::SE3, "se3"},
                                                   {Alignment::Sim3, "sim3"}};
}  // namespace

std::string toString(Alignment alignment) { return enumName(kAlignmentNames, alignment, "none"); }

Alignment parseAlignment(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (const auto alignment = enumValue(kAlignmentNames, n)) return *alignment;
  throw InputError("unknown alignment '" + name + "': expected none, se2, se3 or sim3");
}

SimilarityTransform alignPoints(const std::vector<Eigen::Vector3d>& ref,
                                const std::vector<Eigen::Vector3d>& est, Alignment alignment) {
  if (ref.size() != est.size()) {
    throw InputError("alignment needs as many reference as estimate points");
  }
  SimilarityTransform out;
  if (alignment == Alignment::None) return out;
  const std::size_t needed = alignment == Alignment::SE2 ? 2 : 3;
  if (ref.size() < needed) {
    throw InputError(
        eval_detail::format("%s alignment needs at least %zu associated poses, got %zu",
                            toString(alignment).c_str(), needed, ref.size()));
  }
  const int dim = alignment == Alignment::SE2 ? 2 : 3;
  const auto n = static_cast<Eigen::Index>(ref.size());
  Eigen::MatrixXd src(dim, n), dst(dim, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(i) = est[static_cast<std::size_t>(i)].head(dim);
    dst.col(i) = ref[static_cast<std::size_t>(i)].head(dim);
  }
  const Eigen::VectorXd mean = src.rowwise().mean();
  if ((src.colwise() - mean).colwise().norm().maxCoeff() < 1e-12) {
    throw InputError(toString(alignment) +
                     " alignment is undefined: all associated estimate positions are identical");
  }
  const Eigen::MatrixXd t = Eigen::umeyama(src, dst, alignment == Alignment::Sim3);
  const Eigen::MatrixXd cr = t.topLeftCorner(dim, dim);
  if (alignment == Alignment::Sim3) {
    // Umeyama returns c*R; the columns of R are unit, so the scale is a column norm.
    out.scale = cr.col(0).norm();
    out.rotation = cr / out.scale;
  } else {
    out.rotation.topLeftCorner(dim, dim) = cr;
  }
  out.translation.head(dim) = t.topRightCorner(dim, 1);
  return out;
}

AteResult computeAte(const Trajectory& reference, const Trajectory& estimate,
                     const AteOptions& options) {
  const std::vector<PosePair> pairs = associate(reference, estimate, options.association);
  std::vector<Eigen::Vector3d> ref, est;
  ref.reserve(pairs.size());
  est.reserve(pairs.size());
  for (const PosePair& p : pairs) {
    ref.push_back(reference[p.ref].pose.translation());
    est.push_back(estimate[p.est].pose.translation());
  }
  AteResult result;
  result.alignment = options.alignment;
  result.reference_poses = reference.size();
  result.estimate_poses = estimate.size();
  result.transform = alignPoints(ref, est, options.alignment);
  const SimilarityTransform& s = result.transform;
  std::vector<double> rot_errors;
  result.translation_errors.reserve(pairs.size());
  rot_errors.reserve(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const Eigen::Vector3d aligned = s.scale * (s.rotation * est[k]) + s.translation;
    result.translation_errors.push_back((ref[k] - aligned).norm());
    const Eigen::Matrix3d r_ref = reference[pairs[k].ref].pose.linear();
    const Eigen::Matrix3d r_est = s.rotation * estimate[pairs[k].est].pose.linear();
    rot_errors.push_back(rotationAngle(r_ref.transpose() * r_est) * kRadToDeg);
  }
  result.translation = computeErrorStats(result.translation_errors);
  result.pairs = pairs;
  result.rotation_deg = computeErrorStats(rot_errors);
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
