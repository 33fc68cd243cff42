#include "plugslam/landmarks/appearance_validator.h"

#include <spdlog/spdlog.h>

#include "plugslam/geometry.h"
#include "plugslam/landmarks/landmark_map.h"
#include "plugslam/landmarks/point_registration.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// Information of candidate <- query from the inliers' point residuals, in the right-perturbation
// tangent space of Space3D (T * exp(t, w)): r = T q - c, dr/d(t, w) = R [I, -[q]x].
Eigen::MatrixXd registrationInformation(const DescribedPoints& query, const DescribedPoints& cand,
                                        const std::vector<PointMatch>& inliers,
                                        const Eigen::Isometry3d& t) {
  Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
  const Eigen::Matrix3d r = t.linear();
  for (const PointMatch& m : inliers) {
    const auto s = static_cast<size_t>(m.source), g = static_cast<size_t>(m.target);
    const Eigen::Vector3d& q = query.points[s];
    Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() * 1e-6;
    if (!query.covariances.empty()) cov += r * query.covariances[s] * r.transpose();
    if (!cand.covariances.empty()) cov += cand.covariances[g];
    Eigen::Matrix<double, 3, 6> j;
    j.leftCols<3>() = r;
    j.rightCols<3>() = -r * skew(q);
    h += j.transpose() * cov.inverse() * j;
  }
  return h;
}

}  // namespace

bool AppearanceValidator::count(Outcome o) {
  counts_[o].fetch_add(1, std::memory_order_relaxed);
  return o == kAccepted;
}

bool AppearanceValidator::validate(const LocalMap& candidate, const LocalMap& query,
                                   const Eigen::Isometry3d& guess, LoopClosure& closure,
                                   std::string& reason) {
  const LandmarkMap* c = candidate.scene.find<LandmarkMap>(scene());
  const LandmarkMap* q = query.scene.find<LandmarkMap>(scene());
  if (c == nullptr || q == nullptr || c->empty() || q->empty() ||
      c->descriptor_bytes != q->descriptor_bytes) {
    reason = "no landmarks (scene entry '" + scene() + "') to register";
    return count(kNoLandmarks);
  }
  const DescribedPoints source = describedPoints(*q), target = describedPoints(*c);
  DescriptorMatchOptions match;
  match.max_hamming = max_hamming();
  match.ratio = ratio();
  match.mutual = true;
  const std::vector<PointMatch> matches = matchDescriptors(source, target, match);
  if (static_cast<int>(matches.size()) < min_inliers()) {
    reason = std::to_string(matches.size()) + " descriptor matches, fewer than " +
             std::to_string(min_inliers());
    return count(kFewMatches);
  }
  RansacOptions ransac;
  ransac.max_iterations = iterations();
  ransac.inlier_chi2 = inlier_chi2();
  ransac.min_inliers = min_inliers();
  // The seed follows the pair, so a replay validates the same way whatever the thread timing.
  ransac.seed = static_cast<uint64_t>(candidate.id) * 1000003u + static_cast<uint64_t>(query.id);
  const PointRegistration reg = registerMatches(source, target, matches, ransac);
  if (!reg.valid) {
    reason = std::to_string(reg.inliers.size()) + " of " + std::to_string(matches.size()) +
             " matches agree on a rigid motion, fewer than " + std::to_string(min_inliers());
    return count(kFewInliers);
  }
  const double inlier_ratio =
      static_cast<double>(reg.inliers.size()) / static_cast<double>(matches.size());
  if (inlier_ratio < min_inlier_ratio()) {
    reason = "inlier ratio " + std::to_string(inlier_ratio) + " below " +
             std::to_string(min_inlier_ratio()) + " (" + std::to_string(reg.inliers.size()) +
             " of " + std::to_string(matches.size()) + ")";
    return count(kInlierRatio);
  }
  const double correction = (reg.target_from_source.translation() - guess.translation()).norm();
  if (max_correction() > 0 && correction > max_correction()) {
    reason = "registered pose " + std::to_string(correction) + " m from the estimate";
    return count(kCorrection);
  }
  closure.edge.relative = reg.target_from_source;
  closure.edge.information =
      registrationInformation(source, target, reg.inliers, reg.target_from_source);
  closure.overlap = static_cast<double>(reg.inliers.size()) / static_cast<double>(source.size());
  closure.residual = 0;
  // The margins a rejection's reason gives, for an accepted loop too (how near its gates it is).
  spdlog::debug("{}: map {} -> {}: {} of {} matches agree on a rigid motion (ratio {:.3f})",
                name(), query.id, candidate.id, reg.inliers.size(), matches.size(), inlier_ratio);
  return count(kAccepted);
}

std::vector<Statistic> AppearanceValidator::statistics() const {
  uint64_t checked = 0;
  for (const auto& n : counts_) checked += n.load(std::memory_order_relaxed);
  const auto at = [&](Outcome o) { return static_cast<double>(counts_[o].load()); };
  return {{"checked", static_cast<double>(checked)},
          {"accepted", at(kAccepted)},
          {"rejected_no_landmarks", at(kNoLandmarks)},
          {"rejected_few_matches", at(kFewMatches)},
          {"rejected_few_inliers", at(kFewInliers)},
          {"rejected_inlier_ratio", at(kInlierRatio)},
          {"rejected_correction", at(kCorrection)}};
}

}  // namespace abi_v1
}  // namespace plugslam
