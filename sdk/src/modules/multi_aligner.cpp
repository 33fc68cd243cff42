#include "plugslam/multi_aligner.h"

#include <spdlog/spdlog.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

FactorObserver::~FactorObserver() = default;

const char* toString(AlignFailure failure) {
  switch (failure) {
    case AlignFailure::none:
      return "none";
    case AlignFailure::no_data:
      return "no_data";
    case AlignFailure::too_few_inliers:
      return "too_few_inliers";
    case AlignFailure::degenerate:
      return "degenerate";
    case AlignFailure::slid:
      return "slid";
  }
  return "unknown";
}

std::string describeCues(const std::vector<CueStats>& cues) {
  std::string out;
  for (const CueStats& c : cues) {
    const size_t dot = c.slice.rfind('.');
    out +=
        (out.empty() ? "" : "; ") + (dot == std::string::npos ? c.slice : c.slice.substr(dot + 1));
    out += ": " + std::to_string(c.inliers) + (c.inliers == 1 ? " inlier of " : " inliers of ") +
           std::to_string(c.factors) + (c.factors == 1 ? " factor" : " factors");
    if (c.candidates) out += ", " + std::to_string(c.candidates) + " candidates";
  }
  return out;
}

namespace {

// Binds a slice's entries: raw and measurement ones to the frame, scene ones to the
// scene. False when one is absent.
bool bindEntries(const std::vector<EntryBase*>& entries, const Frame& frame,
                 const PropertyContainer& scene) {
  bool present = true;
  for (EntryBase* entry : entries) {
    const Container c = entry->container();
    entry->bind(c == Container::scene ? &scene
                : c == Container::raw ? &frame.raw
                                      : &frame.measurement);
    present = present && entry->bound();
  }
  return present;
}

template <class S>
AlignContext<S> ofFrame(const AlignContext<S>& context, const Frame& frame) {
  AlignContext<S> frame_context = context;
  frame_context.seq = frame.seq;
  frame_context.stamp = frame.stamp;
  return frame_context;
}

}  // namespace

template <class S>
AlignerSlice<S>::~AlignerSlice() = default;

template <class S>
bool AlignerSlice<S>::bind(const Frame& frame, const PropertyContainer& scene,
                           const AlignContext<S>& context) {
  if (!bindEntries(entries(), frame, scene)) return false;
  return prepare(ofFrame(context, frame));
}

template <class S>
MultiAligner<S>::MultiAligner() = default;
template <class S>
MultiAligner<S>::~MultiAligner() = default;

template <class S>
void MultiAligner<S>::configure() {
  const auto pair = [](const Param<std::vector<double>>& p) {
    if (p().size() != 2)
      throw ParamError(p.name(), "expected 2 values (translation m, rotation rad), got " +
                                     std::to_string(p().size()));
    for (double v : p())
      if (!(v > 0)) throw ParamError(p.name(), "every value must be > 0");
  };
  pair(max_window);
  pair(distinct);
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The prior's error e = log(Z^-1 T) and its Jacobian w.r.t. T's right perturbation: exact in 2D
// (blockdiag(R(E), 1)); in 3D the rotation block is the identity, exact to first order in the
// error, which a prior that holds keeps small.
template <class S>
typename S::Vector priorError(const typename S::Pose& prior, const typename S::Pose& t,
                              typename S::Matrix& j) {
  const typename S::Pose e = prior.inverse() * t;
  j.setIdentity();
  j.template topLeftCorner<S::kDim, S::kDim>() = e.linear();
  return S::toVector(e);
}

}  // namespace

template <class S>
std::pair<double, double> MultiAligner<S>::window(const typename S::Matrix& covariance) const {
  // search_sigmas standard deviations of the prediction's largest translation uncertainty, and
  // of its heading's (the last tangent coordinate in 2D and 3D alike).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, S::kDim, S::kDim>> eig(
      covariance.template topLeftCorner<S::kDim, S::kDim>());
  const double sigma_t = std::sqrt(std::max(0.0, eig.eigenvalues().maxCoeff()));
  const double sigma_r = std::sqrt(std::max(0.0, covariance(S::kDof - 1, S::kDof - 1)));
  return {std::min(max_window()[0], search_sigmas() * sigma_t),
          std::min(max_window()[1], search_sigmas() * sigma_r)};
}

template <class S>
SearchResult<S> MultiAligner<S>::search(const std::vector<ScoringSlice<S>*>& scorers,
                                        const Pose& guess, const typename S::Matrix* prior,
                                        std::pair<double, double> window,
                                        SearchLattice<S>& lattice,
                                        std::vector<const LatticeScorer*>& ready) {
  const auto [linear, angular] = window;
  lattice.center = guess;
  lattice.resolution = search_resolution();
  double step = M_PI;
  for (const ScoringSlice<S>* s : scorers) {
    const double a = s->angularStep(lattice.resolution);
    if (a > 0) step = std::min(step, a);
  }
  lattice.angular_step = step;
  lattice.cells = static_cast<int>(std::ceil(linear / lattice.resolution - 1e-9));
  lattice.angles = static_cast<int>(std::ceil(angular / step - 1e-9));
  lattice.levels = searchLevels(lattice.cells);
  ready.clear();
  for (ScoringSlice<S>* s : scorers)
    if (s->beginSearch(lattice)) ready.push_back(s);
  SearchOptions o;
  o.min_score = min_score();
  o.ambiguity_margin = ambiguity_margin();
  o.distinct_translation = distinct()[0];
  o.distinct_rotation = distinct()[1];
  if (prior) {
    // The lattice moves in the scene's plane: the prior's translation information is taken as
    // isotropic at its least (the largest variance), heading as heading's alone.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, S::kDim, S::kDim>> eig(
        prior->template topLeftCorner<S::kDim, S::kDim>());
    const double vt = eig.eigenvalues().maxCoeff(), vr = (*prior)(S::kDof - 1, S::kDof - 1);
    if (vt > 0 && vr > 0) {
      o.prior_margin = prior_margin();
      o.prior_translation = 1.0 / vt;
      o.prior_rotation = 1.0 / vr;
      o.prior_cap = search_sigmas() * search_sigmas();
    }
  }
  return correlativeSearch(ready, lattice, o);
}

template <class S>
void MultiAligner<S>::check(const std::vector<ScoringSlice<S>*>& scorers, const Pose& guess,
                            const typename S::Matrix* prior, const Pose& start,
                            const SearchLattice<S>& lattice, AlignResult<S>& result) {
  // A solve that ends a distinct peak away from the searched pose went to a minimum the search
  // did not find best (a corridor's slide, a wall pair's swap).
  const Pose moved = S::normalized(start.inverse() * result.pose);
  if (S::distance(moved) > distinct()[0] || S::angle(moved) > distinct()[1]) {
    result.valid = false;
    result.failure = AlignFailure::slid;
    return;
  }
  // A solve that ends outside the window claims an error the prediction's covariance calls
  // implausible, and the search never scored it: a search over a window that covers it must
  // find it best, unambiguously (odometry that slipped), or it slid along what the scan
  // constrains weakly.
  const Pose off = S::normalized(guess.inverse() * result.pose);
  const typename S::Vector v = S::toVector(off);
  const double along = v.template head<S::kDim>().template lpNorm<Eigen::Infinity>();
  const double turned = std::abs(v(S::kDof - 1));
  const double linear = lattice.cells * lattice.resolution;
  const double angular = lattice.angles * lattice.angular_step;
  if (along <= linear + lattice.resolution && turned <= angular + lattice.angular_step) return;
  SearchLattice<S> wide;
  std::vector<const LatticeScorer*> ready;
  const SearchResult<S> again =
      search(scorers, guess, prior,
             {std::min(max_window()[0], std::max(linear, along + lattice.resolution)),
              std::min(max_window()[1], std::max(angular, turned + lattice.angular_step))},
             wide, ready);
  const Pose apart = S::normalized(again.pose.inverse() * result.pose);
  if (!again.found || again.ambiguous || S::distance(apart) > distinct()[0] / 2 ||
      S::angle(apart) > distinct()[1] / 2) {
    result.valid = false;
    result.failure = AlignFailure::slid;
  }
}

template <class S>
AlignResult<S> MultiAligner<S>::align(const Frame& frame, const PropertyContainer& scene,
                                      const AlignContext<S>& given) {
  AlignContext<S> context = given;
  context.search_sigmas = search_sigmas();
  std::vector<AlignerSlice<S>*> active;
  std::vector<ScoringSlice<S>*> scorers;
  std::vector<RecoverableSlice<S>*> recoverable;
  for (auto& slice : slices)
    if (slice->bind(frame, scene, context)) {
      active.push_back(slice.get());
      if (auto* s = dynamic_cast<ScoringSlice<S>*>(slice.get())) scorers.push_back(s);
      if (auto* r = dynamic_cast<RecoverableSlice<S>*>(slice.get())) recoverable.push_back(r);
    }
  AlignResult<S> result;
  result.pose = context.guess;
  result.H.setZero();
  if (active.empty()) return result;
  // Search: where in the prediction's window the cues fit best.
  Pose start = context.guess;
  SearchResult<S> found;
  SearchLattice<S> lattice;
  std::vector<const LatticeScorer*> ready;
  const auto t_search = Clock::now();
  // The prediction's typical error, where this run measured it, weighs the search (a model's
  // stated covariance bounds its error, it is no calibration of it); the bound sets the window.
  const typename S::Matrix* typical = context.typical ? &*context.typical : nullptr;
  const auto mahalanobis = [&](const Pose& p) {
    const typename S::Vector d = S::toVector(S::normalized(context.guess.inverse() * p));
    return d.dot((typical ? *typical : *context.covariance).ldlt().solve(d));
  };
  if (context.covariance && !scorers.empty() && search_sigmas() > 0) {
    found = search(scorers, context.guess, typical, window(*context.covariance), lattice, ready);
    if (found.found && found.ambiguous) {
      // Two distinct poses fit alike: the cues cannot tell them apart, the prediction can.
      if (mahalanobis(found.rival) < mahalanobis(found.pose)) {
        std::swap(found.pose, found.rival);
        std::swap(found.score, found.rival_score);
      }
    }
    if (found.found) start = found.pose;
  }
  const double search_s = since(t_search);
  // Refine: the cues' solve from there, the prediction a factor with its covariance.
  const auto t_refine = Clock::now();
  std::optional<typename S::Matrix> prior_information;
  if (motion_prior() && context.covariance) {
    // The typical error's prior where the search found the pose within its reach; beyond it the
    // motion was not typical, and only its bound is known.
    const double reach = search_sigmas() * search_sigmas();
    const typename S::Matrix& c =
        context.typical && mahalanobis(start) <= reach ? *context.typical : *context.covariance;
    const Eigen::LDLT<typename S::Matrix> ldlt(c);
    if (ldlt.info() == Eigen::Success && ldlt.isPositive())
      prior_information = ldlt.solve(S::Matrix::Identity());
  }
  const Pose* prior = prior_information ? &context.guess : nullptr;
  const typename S::Matrix* info = prior_information ? &*prior_information : nullptr;
  result = solve(active, start, prior, info);
  if (found.found) {
    result.searched = true;
    result.search_score = found.score;
    if (result.valid) check(scorers, context.guess, typical, start, lattice, result);
  }
  // Other hypotheses: the pace kept through a gap in the stamps (its prior is about it), and
  // those made without the prediction (descriptor matching + RANSAC). Each is refined by the
  // ordinary solve (every slice), and the result that explains more of the frame wins.
  const auto hypotheses = [&]() {
    bool made = false;
    const auto compete = [&](const Pose& from, const Pose* about) {
      made = true;
      AlignResult<S> retry = solve(active, from, about, info);
      if (retry.valid && (!result.valid || retry.inliers > result.inliers)) {
        retry.hypothesis = true;
        result = retry;
      }
    };
    if (context.through_gap) compete(*context.through_gap, prior ? &*context.through_gap : nullptr);
    for (RecoverableSlice<S>* r : recoverable)
      if (const std::optional<Pose> proposed = r->recoverPose()) compete(*proposed, prior);
    return made;
  };
  if (relocalise() && !recoverable.empty()) {
    const bool covered = std::all_of(recoverable.begin(), recoverable.end(),
                                     [](const RecoverableSlice<S>* r) { return r->priorCovered(); });
    // An invalid solve, or one the cues could not reach where the prediction may be off, or
    // one that ended where the prediction said it could not be (the cues' windows were set for
    // errors that size: what they paired there may be look-alikes), or one whose cues barely
    // measure the step: a hypothesis without the prediction competes with it. Whatever wins
    // must measure its own step, or it is said to be unchecked.
    const bool measured = result.valid && motionMeasured(context, result, info);
    if (!measured || !covered || !withinWindow(context, result.pose)) {
      const bool made = hypotheses();
      // Only a hypothesis that won changed the pose whose step is judged.
      const bool vouched = result.hypothesis ? motionMeasured(context, result, info) : measured;
      if (result.valid && (!made || !vouched)) result.unchecked = true;
    }
  }
  if (result.valid && found.found && found.ambiguous) {
    // The cues cannot tell the solve from the rival: the covariance must reach the rival, so the
    // information along the way to it is cut to a standard deviation of half that distance
    // (H' = (H^-1 + d d^T / 4)^-1, Sherman-Morrison). The rival is a lattice pose, off by up to
    // half a cell across a corridor's axis, where the cues are sure: when most of the way lies
    // along the direction the cues constrain least, the cut is along that direction alone.
    const typename S::Vector d = S::toVector(S::normalized(result.pose.inverse() * found.rival));
    const Eigen::SelfAdjointEigenSolver<typename S::Matrix> eig(result.H);
    const typename S::Vector weakest = eig.eigenvectors().col(0);
    const double along = weakest.dot(d);
    const typename S::Vector way =
        d.norm() > 0 && std::abs(along) >= 0.5 * d.norm() ? typename S::Vector(along * weakest) : d;
    const typename S::Vector hd = result.H * way;
    result.H -= hd * hd.transpose() / (4.0 + way.dot(hd));
    result.ambiguous = true;
    result.rival = d;
  }
  result.search_s = search_s;
  result.refine_s = since(t_refine);
  return result;
}

template <class S>
bool MultiAligner<S>::withinWindow(const AlignContext<S>& context, const Pose& pose) const {
  if (!context.covariance) return true;
  const auto [linear, angular] = window(*context.covariance);
  const typename S::Vector v = S::toVector(S::normalized(context.guess.inverse() * pose));
  return v.template head<S::kDim>().norm() <= linear &&
         v.template tail<S::kDof - S::kDim>().norm() <= angular;
}

template <class S>
bool MultiAligner<S>::motionMeasured(const AlignContext<S>& context, const AlignResult<S>& result,
                                     const typename S::Matrix* prior_information) const {
  using Mat = typename S::Matrix;
  using Vec = Eigen::Matrix<double, S::kDim, 1>;
  // The data's information alone: the prediction's factor is not a measurement of the step.
  Mat h = result.H;
  if (prior_information) h -= *prior_information;
  const Eigen::LDLT<Mat> ldlt(h);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  const Mat covariance = ldlt.solve(Mat::Identity());
  // The direction of travel in the robot's frame (the tangent's translation block): the solved
  // step's, else the predicted one's; without either, the least measured direction.
  const auto step_in_robot = [&](const Pose& to) -> Vec {
    return to.linear().transpose() * (to.translation() - context.previous.translation());
  };
  Vec step = step_in_robot(result.pose);
  if (step.norm() < 1e-9) step = step_in_robot(context.guess);
  const Eigen::Matrix<double, S::kDim, S::kDim> ctt =
      covariance.template topLeftCorner<S::kDim, S::kDim>();
  Vec d;
  if (step.norm() < 1e-9) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, S::kDim, S::kDim>> eig(ctt);
    d = eig.eigenvectors().col(S::kDim - 1);
  } else {
    d = step.normalized();
  }
  const double sigma = std::sqrt(std::max(0.0, d.dot(ctt * d)));
  const double predicted =
      context.covariance
          ? std::sqrt(std::max(
                0.0, d.dot(context.covariance->template topLeftCorner<S::kDim, S::kDim>() * d)))
          : 0.0;
  spdlog::trace("motion check: step {:.3f} m, its sigma {:.4f} m (the prediction's {:.4f} m)",
                step.norm(), sigma, predicted);
  return 3 * sigma <= step_tolerance() * step.norm() || sigma <= 0.5 * predicted;
}

template <class S>
AlignResult<S> MultiAligner<S>::solve(const std::vector<AlignerSlice<S>*>& active,
                                      const Pose& guess, const Pose* prior_mean,
                                      const typename S::Matrix* prior_information) {
  AlignResult<S> result;
  result.pose = guess;
  result.H.setZero();
  // The direction the information constrains least (the eigenvector of its smallest
  // eigenvalue), for a degenerate result's message.
  const auto degenerate = [&result](const typename S::Matrix& h) {
    Eigen::SelfAdjointEigenSolver<typename S::Matrix> eig(h);
    result.failure = AlignFailure::degenerate;
    result.weakest = eig.eigenvectors().col(0).normalized();
    return result;
  };
  // Each slice sums its own factors from zero (its counts are its cue's), then the slices' sums
  // are added in slice order. chi2 runs on through the slices: it sums in factor order.
  NormalEquations<S> eq;
  std::vector<NormalEquations<S>> parts(active.size());
  auto linearize = [&](const Pose& t) {
    eq.clear();
    for (size_t k = 0; k < active.size(); ++k) {
      NormalEquations<S>& part = parts[k];
      part.clear();
      part.chi2 = eq.chi2;
      active[k]->linearize(t, part);
      eq.H += part.H;
      eq.b += part.b;
      eq.chi2 = part.chi2;
      eq.inliers += part.inliers;
      eq.factors += part.factors;
      eq.candidates += part.candidates;
    }
    // The prediction's factor is not a cue: it adds to the sums, not to the counts.
    if (prior_mean) {
      typename S::Matrix j;
      const typename S::Vector e = priorError<S>(*prior_mean, t, j);
      const typename S::Matrix jt_omega = j.transpose() * *prior_information;
      eq.H += jt_omega * j;
      eq.b += jt_omega * e;
      eq.chi2 += e.dot(*prior_information * e);
    }
  };
  typename S::Pose t = guess;
  for (auto* slice : active) slice->beginSolve();
  for (int outer = 0; outer < outer_iterations(); ++outer) {
    for (auto* slice : active) slice->associate(t);
    bool step_converged = false;
    for (int inner = 0; inner < inner_iterations(); ++inner) {
      linearize(t);
      if (eq.factors == 0) return result;  // failure stays no_data
      typename S::Matrix h = eq.H;
      h.diagonal().array() += damping();
      Eigen::LDLT<typename S::Matrix> ldlt(h);
      if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return degenerate(eq.H);
      typename S::Vector dx = ldlt.solve(-eq.b);
      if (!dx.allFinite()) return degenerate(eq.H);
      t = S::boxplus(t, dx);
      ++result.iterations;
      if (dx.norm() < convergence()) {
        step_converged = true;
        break;
      }
    }
    // Converged when a fresh association no longer moves the estimate.
    if (step_converged && outer > 0) {
      result.converged = true;
      break;
    }
  }
  // Statistics and information at the solution.
  for (auto* slice : active) slice->associate(t);
  linearize(t);
  result.pose = t;
  result.H = eq.H;
  result.chi2 = eq.chi2;
  result.inliers = eq.inliers;
  result.factors = eq.factors;
  result.candidates = eq.candidates;
  result.cues.reserve(active.size());
  for (size_t k = 0; k < active.size(); ++k)
    result.cues.push_back(
        CueStats{active[k]->name(), parts[k].factors, parts[k].inliers, parts[k].candidates});
  // A solution needs enough inliers and a full-rank information matrix.
  Eigen::SelfAdjointEigenSolver<typename S::Matrix> eig(eq.H);
  if (eq.factors == 0) {
    result.failure = AlignFailure::no_data;
  } else if (eq.inliers < static_cast<size_t>(min_inliers())) {
    result.failure = AlignFailure::too_few_inliers;
  } else if (!(eig.eigenvalues().minCoeff() > 1e-9 * std::max(1.0, eig.eigenvalues().maxCoeff()))) {
    result.failure = AlignFailure::degenerate;
    result.weakest = eig.eigenvectors().col(0).normalized();
  } else {
    result.failure = AlignFailure::none;
  }
  result.valid = result.failure == AlignFailure::none;
  return result;
}

template <class S>
RecoverableSlice<S>::~RecoverableSlice() = default;

template class AlignerSlice<Space2D>;
template class AlignerSlice<Space3D>;
template class RecoverableSlice<Space2D>;
template class RecoverableSlice<Space3D>;
template class MultiAligner<Space2D>;
template class MultiAligner<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
