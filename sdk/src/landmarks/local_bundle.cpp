#include "plugslam/landmarks/local_bundle.h"

#include <spdlog/spdlog.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_map>

#include "plugslam/landmarks/observation_factor.h"
#include "plugslam/solver/robust_kernel.h"
#include "plugslam/solver/variable.h"

namespace plugslam {
inline namespace abi_v1 {
namespace {

using Mat36 = Eigen::Matrix<double, 3, 6>;
using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat66 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// One observation of a refined landmark.
struct Term {
  int frame = 0;  // index into the frames
  int pose = -1;  // index among the free poses, -1 for a fixed frame
  int point = 0;  // index among the refined landmarks
  Eigen::Vector3d measured, information;
};

// The normal equations' blocks at one estimate, with the robust cost there.
struct Linearization {
  double cost = 0;
  std::vector<Mat66> hpp;            // per free pose
  Eigen::VectorXd bp;                // per free pose, stacked
  std::vector<Eigen::Matrix3d> hll;  // per landmark
  std::vector<Eigen::Vector3d> bl;   // per landmark
  std::vector<Mat63> hpl;            // per term: Jp^T W Jl (zero for a fixed frame)
};

// The bundle's normal equations have one 3x3 block per landmark and a few 6x6 blocks per pose:
// eliminating the landmarks (Schur complement) leaves a dense system of the free poses alone,
// 6 unknowns per frame, solved directly. Each Levenberg-Marquardt step thus costs a pass over
// the observations, not the factorisation of thousands of unknowns.
class SchurBundle {
 public:
  SchurBundle(std::vector<BundleFrame>& frames, std::vector<Eigen::Vector3d>& points,
              std::vector<Term> terms, const RobustKernel& kernel)
      : frames_(frames), points_(points), kernel_(kernel) {
    // An observation already behind its camera is an outlier the cost cannot weigh: left out.
    for (const Term& t : terms) {
      Eigen::Vector3d e;
      const BundleFrame& f = frames_[t.frame];
      if (observationError(f.pose, f.mount, f.camera, points_[t.point], t.measured, e, nullptr,
                           nullptr))
        terms_.push_back(t);
    }
    for (size_t k = 0; k < frames_.size(); ++k)
      if (!frames_[k].fixed) free_.push_back(static_cast<int>(k));
    std::vector<int> pose_of(frames_.size(), -1);
    for (size_t i = 0; i < free_.size(); ++i) pose_of[free_[i]] = static_cast<int>(i);
    by_point_.resize(points_.size());
    for (size_t t = 0; t < terms_.size(); ++t) {
      terms_[t].pose = pose_of[terms_[t].frame];
      by_point_[terms_[t].point].push_back(static_cast<int>(t));
    }
  }

  // Levenberg-Marquardt (Nielsen's damping update, as the SDK's optimizer); returns the cost
  // before and after. A step's cost comes with its linearisation (the next iteration's), so an
  // accepted step costs one pass over the observations.
  std::pair<double, double> run(int iterations) {
    linearize(now_);
    const double initial = now_.cost;
    double lambda = -1, nu = 2;
    std::vector<Eigen::Isometry3d> poses_before(free_.size());
    std::vector<Eigen::Vector3d> points_before;
    for (int it = 0; it < iterations && std::isfinite(now_.cost); ++it) {
      if (lambda < 0) {
        double max_diag = 0;
        for (const Mat66& h : now_.hpp) max_diag = std::max(max_diag, h.diagonal().maxCoeff());
        for (const Eigen::Matrix3d& h : now_.hll)
          max_diag = std::max(max_diag, h.diagonal().maxCoeff());
        lambda = 1e-8 * std::max(max_diag, 1e-12);
      }
      bool accepted = false;
      for (int rejected = 0; rejected <= 10 && !accepted; ++rejected) {
        if (!solve(lambda)) {
          lambda *= nu;
          nu *= 2;
          continue;
        }
        for (size_t i = 0; i < free_.size(); ++i) poses_before[i] = frames_[free_[i]].pose;
        points_before = points_;
        apply();
        linearize(next_);
        const double chi = now_.cost, new_chi = next_.cost;
        const double predicted =
            lambda * (dxp_.squaredNorm() + dxlSquaredNorm()) - dxp_.dot(now_.bp) - dxlDotB();
        const double rho = (chi - new_chi) / predicted;
        if (std::isfinite(new_chi) && predicted > 0 && rho > 0) {
          const double t = 2 * rho - 1;
          lambda *= std::max(1.0 / 3.0, 1 - t * t * t);
          nu = 2;
          std::swap(now_, next_);
          accepted = true;
          if ((chi - new_chi) < 1e-6 * std::max(chi, std::numeric_limits<double>::min()))
            return {initial, now_.cost};
        } else {
          for (size_t i = 0; i < free_.size(); ++i) frames_[free_[i]].pose = poses_before[i];
          points_.swap(points_before);
          lambda *= nu;
          nu *= 2;
        }
      }
      if (!accepted) break;
    }
    return {initial, now_.cost};
  }

 private:
  // H, b and the robust cost at the current estimates, with the robust weight rho'(chi2) on
  // each observation; the cost is +inf when a landmark fell behind a camera that saw it.
  void linearize(Linearization& l) const {
    l.cost = 0;
    l.hpp.assign(free_.size(), Mat66::Zero());
    l.bp = Eigen::VectorXd::Zero(6 * static_cast<Eigen::Index>(free_.size()));
    l.hll.assign(points_.size(), Eigen::Matrix3d::Zero());
    l.bl.assign(points_.size(), Eigen::Vector3d::Zero());
    l.hpl.resize(terms_.size());
    for (size_t i = 0; i < terms_.size(); ++i) {
      const Term& t = terms_[i];
      const BundleFrame& f = frames_[t.frame];
      Eigen::Vector3d e;
      Mat36 jp;
      Eigen::Matrix3d jl;
      if (!observationError(f.pose, f.mount, f.camera, points_[t.point], t.measured, e,
                            t.pose >= 0 ? &jp : nullptr, &jl)) {
        l.cost = std::numeric_limits<double>::infinity();
        return;
      }
      const Eigen::Vector3d omega = t.information;
      const Eigen::Vector3d rho = kernel_.robustify(e.dot(omega.asDiagonal() * e));
      l.cost += rho[0];
      const Eigen::Vector3d w = rho[1] * omega;
      const Eigen::Vector3d we = w.cwiseProduct(e);
      const Eigen::Matrix3d wjl = w.asDiagonal() * jl;
      l.hll[t.point].noalias() += jl.transpose() * wjl;
      l.bl[t.point].noalias() += jl.transpose() * we;
      if (t.pose < 0) continue;
      l.hpp[t.pose].noalias() += jp.transpose() * (w.asDiagonal() * jp);
      l.bp.segment<6>(6 * t.pose).noalias() += jp.transpose() * we;
      l.hpl[i].noalias() = jp.transpose() * wjl;
    }
  }

  // The step for damping lambda: (H + lambda I) dx = -b, landmarks eliminated.
  bool solve(double lambda) {
    const Linearization& l = now_;
    const Eigen::Index n = 6 * static_cast<Eigen::Index>(free_.size());
    s_.setZero(n, n);
    Eigen::VectorXd r = -l.bp;
    for (size_t i = 0; i < free_.size(); ++i)
      s_.block<6, 6>(6 * i, 6 * i) = l.hpp[i] + lambda * Mat66::Identity();
    hll_inv_.resize(points_.size());
    for (size_t j = 0; j < points_.size(); ++j) {
      const Eigen::Matrix3d h = l.hll[j] + lambda * Eigen::Matrix3d::Identity();
      Eigen::LDLT<Eigen::Matrix3d> ldlt(h);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
          ldlt.vectorD().minCoeff() <= 1e-12 * std::max(1.0, h.diagonal().maxCoeff()))
        return false;
      hll_inv_[j] = ldlt.solve(Eigen::Matrix3d::Identity());
      // S -= Hpl Hll^-1 Hlp over every pair of free poses that saw this landmark.
      for (int a : by_point_[j]) {
        const int pa = terms_[a].pose;
        if (pa < 0) continue;
        const Mat63 ha = l.hpl[a] * hll_inv_[j];
        r.segment<6>(6 * pa).noalias() += ha * l.bl[j];
        for (int b : by_point_[j]) {
          const int pb = terms_[b].pose;
          if (pb < pa) continue;
          const Mat66 blk = ha * l.hpl[b].transpose();
          s_.block<6, 6>(6 * pa, 6 * pb) -= blk;
          if (pb != pa) s_.block<6, 6>(6 * pb, 6 * pa) -= blk.transpose();
        }
      }
    }
    dxp_ = Eigen::VectorXd::Zero(n);
    if (n > 0) {
      Eigen::LDLT<Eigen::MatrixXd> ldlt(s_);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
      dxp_ = ldlt.solve(r);
      if (!dxp_.allFinite()) return false;
    }
    // Back-substitution: dl = Hll^-1 (-bl - Hlp dp).
    dxl_.resize(points_.size());
    for (size_t j = 0; j < points_.size(); ++j) {
      Eigen::Vector3d rhs = -l.bl[j];
      for (int a : by_point_[j])
        if (terms_[a].pose >= 0)
          rhs.noalias() -= l.hpl[a].transpose() * dxp_.segment<6>(6 * terms_[a].pose);
      dxl_[j] = hll_inv_[j] * rhs;
    }
    return true;
  }

  void apply() {
    for (size_t i = 0; i < free_.size(); ++i)
      frames_[free_[i]].pose = VariableSE3::oplusTo(frames_[free_[i]].pose, dxp_.data() + 6 * i);
    for (size_t j = 0; j < points_.size(); ++j) points_[j] += dxl_[j];
  }

  double dxlSquaredNorm() const {
    double s = 0;
    for (const Eigen::Vector3d& d : dxl_) s += d.squaredNorm();
    return s;
  }
  double dxlDotB() const {
    double s = 0;
    for (size_t j = 0; j < dxl_.size(); ++j) s += dxl_[j].dot(now_.bl[j]);
    return s;
  }

  std::vector<BundleFrame>& frames_;
  std::vector<Eigen::Vector3d>& points_;
  std::vector<Term> terms_;
  const RobustKernel& kernel_;
  std::vector<int> free_;                   // the frames whose poses move
  std::vector<std::vector<int>> by_point_;  // each landmark's terms
  Linearization now_, next_;                // at the estimate, and at a step tried from it
  Eigen::MatrixXd s_;                       // the reduced system
  Eigen::VectorXd dxp_;
  std::vector<Eigen::Matrix3d> hll_inv_;
  std::vector<Eigen::Vector3d> dxl_;
};

}  // namespace

BundleResult adjustBundle(std::vector<BundleFrame>& frames, LandmarkMap& map,
                          const BundleOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  BundleResult result;
  std::unordered_map<uint64_t, size_t> index;  // track id -> position in the map
  index.reserve(map.size());
  for (size_t j = 0; j < map.size(); ++j) index.emplace(map.ids[j], j);
  // A landmark seen by one frame only is fixed by that frame alone: it adds unknowns, no check.
  // One that no moving frame saw was settled while its frames moved (in an earlier bundle): it
  // costs the solve as much and changes no pose. Without a moving frame, the landmarks alone.
  const bool any_free =
      std::any_of(frames.begin(), frames.end(), [](const BundleFrame& f) { return !f.fixed; });
  std::unordered_map<uint64_t, std::pair<int, bool>> seen;  // frames, and whether one moves
  for (const BundleFrame& f : frames)
    for (const BundleObservation& o : f.observations)
      if (index.count(o.landmark)) {
        auto& [count, by_free] = seen[o.landmark];
        ++count;
        by_free = by_free || !f.fixed || !any_free;
      }

  std::unordered_map<uint64_t, int> point_of;  // track id -> index among the refined
  std::vector<uint64_t> ids;
  std::vector<Eigen::Vector3d> points;
  std::vector<Term> terms;
  for (size_t k = 0; k < frames.size(); ++k)
    for (const BundleObservation& o : frames[k].observations) {
      const auto s = seen.find(o.landmark);
      if (s == seen.end() || s->second.first < 2 || !s->second.second) continue;
      auto [it, added] = point_of.emplace(o.landmark, static_cast<int>(points.size()));
      if (added) {
        ids.push_back(o.landmark);
        points.push_back(map.positions[index.at(o.landmark)]);
      }
      Term t;
      t.frame = static_cast<int>(k);
      t.point = it->second;
      t.measured = o.measured;
      t.information = o.information;
      terms.push_back(t);
    }
  result.frames = static_cast<int>(frames.size());
  result.landmarks = static_cast<int>(points.size());
  result.observations = static_cast<int>(terms.size());
  if (points.empty()) return result;

  const std::shared_ptr<const RobustKernel> kernel =
      makeRobustKernel("huber", options.kernel_scale);
  std::vector<BundleFrame> refined = frames;
  SchurBundle bundle(refined, points, std::move(terms), *kernel);
  std::tie(result.chi2_before, result.chi2_after) = bundle.run(options.iterations);
  spdlog::trace(
      "bundle: {} frames, {} landmarks, {} observations: chi2 {:.1f} -> {:.1f}, {:.2f} "
      "ms",
      result.frames, result.landmarks, result.observations, result.chi2_before, result.chi2_after,
      1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (!(result.chi2_after < result.chi2_before)) return result;
  for (size_t j = 0; j < ids.size(); ++j) map.positions[index.at(ids[j])] = points[j];
  for (size_t k = 0; k < frames.size(); ++k) frames[k].pose = refined[k].pose;
  map.touch();
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
