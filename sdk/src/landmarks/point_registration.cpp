#include "plugslam/landmarks/point_registration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace plugslam {
inline namespace abi_v1 {

namespace {
// Covariance of point i, unit when the set has none (distances are then in metres).
const Eigen::Matrix3d& covarianceOf(const DescribedPoints& p, size_t i) {
  static const Eigen::Matrix3d unit = Eigen::Matrix3d::Identity();
  return p.covariances.empty() ? unit : p.covariances[i];
}

// Weighted least-squares rigid fit (Horn / Kabsch by SVD): target <- source.
bool fitRigid(const std::vector<Eigen::Vector3d>& s, const std::vector<Eigen::Vector3d>& t,
              const std::vector<double>& w, Eigen::Isometry3d& out) {
  double wsum = 0;
  Eigen::Vector3d cs = Eigen::Vector3d::Zero(), ct = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < s.size(); ++i) {
    cs += w[i] * s[i];
    ct += w[i] * t[i];
    wsum += w[i];
  }
  if (!(wsum > 0)) return false;
  cs /= wsum;
  ct /= wsum;
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < s.size(); ++i) h += w[i] * (s[i] - cs) * (t[i] - ct).transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixV() * svd.matrixU().transpose()).determinant() < 0) d(2, 2) = -1;
  const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();
  if (!r.allFinite()) return false;
  out = Eigen::Isometry3d::Identity();
  out.linear() = r;
  out.translation() = ct - r * cs;
  return true;
}

// Squared Mahalanobis distance of a match under the transform (both points' covariances, the
// source's rotated into the target frame).
double matchChi2(const DescribedPoints& source, const DescribedPoints& target,
                 const PointMatch& m, const Eigen::Isometry3d& tf) {
  const size_t si = static_cast<size_t>(m.source), ti = static_cast<size_t>(m.target);
  const Eigen::Vector3d r = target.points[ti] - tf * source.points[si];
  const Eigen::Matrix3d& rot = tf.linear();
  Eigen::Matrix3d c = covarianceOf(target, ti) + rot * covarianceOf(source, si) * rot.transpose();
  c.diagonal().array() += 1e-12;  // a point measured exactly still has a finite gate
  return r.dot(c.ldlt().solve(r));
}

// Variance of the distance between two points of one set (isotropic approximation).
double distanceVariance(const DescribedPoints& p, size_t i, size_t j) {
  return covarianceOf(p, i).trace() / 3.0 + covarianceOf(p, j).trace() / 3.0;
}

void countInliers(const DescribedPoints& source, const DescribedPoints& target,
                  const std::vector<PointMatch>& matches, const Eigen::Isometry3d& tf,
                  double gate, std::vector<int>& inliers) {
  inliers.clear();
  for (size_t k = 0; k < matches.size(); ++k)
    if (matchChi2(source, target, matches[k], tf) < gate) inliers.push_back(static_cast<int>(k));
}

// Refits on the inliers, weighting each by the inverse of its summed covariance's trace, and
// re-selects them; a few rounds settle both.
Eigen::Isometry3d refit(const DescribedPoints& source, const DescribedPoints& target,
                        const std::vector<PointMatch>& matches, Eigen::Isometry3d tf, double gate,
                        std::vector<int>& inliers) {
  std::vector<Eigen::Vector3d> s, t;
  std::vector<double> w;
  for (int round = 0; round < 3 && inliers.size() >= 3; ++round) {
    s.clear();
    t.clear();
    w.clear();
    for (int k : inliers) {
      const PointMatch& m = matches[static_cast<size_t>(k)];
      s.push_back(source.points[static_cast<size_t>(m.source)]);
      t.push_back(target.points[static_cast<size_t>(m.target)]);
      const double var = covarianceOf(source, static_cast<size_t>(m.source)).trace() +
                         covarianceOf(target, static_cast<size_t>(m.target)).trace();
      w.push_back(1.0 / std::max(var, 1e-12));
    }
    Eigen::Isometry3d next;
    if (!fitRigid(s, t, w, next)) break;
    std::vector<int> again;
    countInliers(source, target, matches, next, gate, again);
    if (again.size() < inliers.size()) break;  // the refit must not lose support
    tf = next;
    inliers.swap(again);
  }
  return tf;
}

// True when the points are spread in at least two directions (three collinear points, or all
// inliers on one line, leave the rotation about that line free).
bool wellSpread(const std::vector<Eigen::Vector3d>& p) {
  if (p.size() < 3) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& x : p) mean += x;
  mean /= static_cast<double>(p.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& x : p) scatter += (x - mean) * (x - mean).transpose();
  scatter /= static_cast<double>(p.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  // Second-largest spread at least 1 mm (std. dev.) and a thousandth of the largest.
  return eig.eigenvalues()(1) > 1e-6 && eig.eigenvalues()(1) > 1e-6 * eig.eigenvalues()(2);
}
}  // namespace

DescribedPoints describedPoints(const FeatureSet& features) {
  DescribedPoints out;
  out.descriptor_bytes = features.descriptor_bytes;
  for (size_t i = 0; i < features.size(); ++i) {
    if (!features.hasDepth(i)) continue;
    out.points.push_back(features.points[i]);
    out.covariances.push_back(features.covariances[i]);
    out.descriptors.insert(out.descriptors.end(), features.descriptor(i),
                           features.descriptor(i) + features.descriptor_bytes);
    out.source_index.push_back(static_cast<int>(i));
  }
  return out;
}

DescribedPoints describedPoints(const LandmarkMap& map) {
  DescribedPoints out;
  out.descriptor_bytes = map.descriptor_bytes;
  out.points = map.positions;
  out.covariances = map.covariances;
  out.descriptors = map.descriptors;
  out.source_index.resize(map.size());
  for (size_t i = 0; i < map.size(); ++i) out.source_index[i] = static_cast<int>(i);
  return out;
}

std::vector<PointMatch> matchDescriptors(const DescribedPoints& source,
                                         const DescribedPoints& target,
                                         const DescriptorMatchOptions& options) {
  std::vector<PointMatch> out;
  if (source.size() == 0 || target.size() == 0 ||
      source.descriptor_bytes != target.descriptor_bytes)
    return out;
  const int bytes = source.descriptor_bytes;
  constexpr int kNone = std::numeric_limits<int>::max();
  // Best source of each target, for the mutual check.
  std::vector<int> best_source(target.size(), -1), best_source_d(target.size(), kNone);
  std::vector<PointMatch> candidates;
  candidates.reserve(source.size());
  for (size_t i = 0; i < source.size(); ++i) {
    int best = kNone, second = kNone, best_j = -1;
    const uint8_t* a = source.descriptor(i);
    for (size_t j = 0; j < target.size(); ++j) {
      const int d = hammingDistance(a, target.descriptor(j), bytes);
      if (d < best) {
        second = best;
        best = d;
        best_j = static_cast<int>(j);
      } else if (d < second) {
        second = d;
      }
      if (d < best_source_d[j]) {
        best_source_d[j] = d;
        best_source[j] = static_cast<int>(i);
      }
    }
    if (best_j < 0 || best > options.max_hamming) continue;
    if (options.ratio < 1.0 && second != kNone &&
        static_cast<double>(best) >= options.ratio * static_cast<double>(second))
      continue;
    candidates.push_back({static_cast<int>(i), best_j, best});
  }
  for (const PointMatch& m : candidates)
    if (!options.mutual || best_source[static_cast<size_t>(m.target)] == m.source)
      out.push_back(m);
  return out;
}

PointRegistration registerMatches(const DescribedPoints& source, const DescribedPoints& target,
                                  const std::vector<PointMatch>& matches,
                                  const RansacOptions& options) {
  PointRegistration result;
  result.matches = matches.size();
  const size_t n = matches.size();
  if (n < 3 || n < static_cast<size_t>(std::max(options.min_inliers, 3))) return result;
  std::mt19937_64 rng(options.seed);
  std::uniform_int_distribution<size_t> pick(0, n - 1);
  std::vector<int> best, current;
  Eigen::Isometry3d best_tf = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> s(3), t(3);
  const std::vector<double> w(3, 1.0);
  int needed = options.max_iterations;
  int it = 0;
  for (; it < needed; ++it) {
    size_t k[3];
    k[0] = pick(rng);
    do k[1] = pick(rng); while (k[1] == k[0]);
    do k[2] = pick(rng); while (k[2] == k[0] || k[2] == k[1]);
    bool consistent = true;
    for (int a = 0; a < 3; ++a) {
      s[a] = source.points[static_cast<size_t>(matches[k[a]].source)];
      t[a] = target.points[static_cast<size_t>(matches[k[a]].target)];
    }
    // A rigid motion keeps distances: reject samples whose pairwise distances disagree by more
    // than 3 sigma before fitting (most wrong samples end here, cheaply).
    for (int a = 0; a < 3 && consistent; ++a) {
      const int b = (a + 1) % 3;
      const double ds = (s[a] - s[b]).norm(), dt = (t[a] - t[b]).norm();
      const double var =
          distanceVariance(source, static_cast<size_t>(matches[k[a]].source),
                           static_cast<size_t>(matches[k[b]].source)) +
          distanceVariance(target, static_cast<size_t>(matches[k[a]].target),
                           static_cast<size_t>(matches[k[b]].target));
      if ((ds - dt) * (ds - dt) > 9.0 * var) consistent = false;
    }
    if (!consistent || !wellSpread(s)) continue;
    Eigen::Isometry3d tf;
    if (!fitRigid(s, t, w, tf)) continue;
    countInliers(source, target, matches, tf, options.inlier_chi2, current);
    if (current.size() > best.size()) {
      best.swap(current);
      best_tf = tf;
      // Samples needed to draw one all-inlier triple with the requested confidence.
      const double ratio = static_cast<double>(best.size()) / static_cast<double>(n);
      const double p3 = ratio * ratio * ratio;
      if (p3 >= 1.0 - 1e-12) {
        needed = std::min(needed, it + 1);
      } else {
        const double k_needed = std::log(1.0 - options.confidence) / std::log(1.0 - p3);
        if (k_needed < static_cast<double>(needed)) needed = static_cast<int>(std::ceil(k_needed));
      }
    }
  }
  result.iterations = it;
  if (best.size() < 3) return result;
  best_tf = refit(source, target, matches, best_tf, options.inlier_chi2, best);
  result.target_from_source = best_tf;
  std::vector<Eigen::Vector3d> spread;
  spread.reserve(best.size());
  for (int k : best) {
    result.inliers.push_back(matches[static_cast<size_t>(k)]);
    spread.push_back(source.points[static_cast<size_t>(matches[static_cast<size_t>(k)].source)]);
  }
  result.valid =
      result.inliers.size() >= static_cast<size_t>(options.min_inliers) && wellSpread(spread);
  return result;
}

PointRegistration registerPoints(const DescribedPoints& source, const DescribedPoints& target,
                                 const DescriptorMatchOptions& match,
                                 const RansacOptions& ransac) {
  return registerMatches(source, target, matchDescriptors(source, target, match), ransac);
}

}  // namespace abi_v1
}  // namespace plugslam
