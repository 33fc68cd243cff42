#include "plugslam/multi_aligner.h"

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

FactorObserver::~FactorObserver() = default;

const char* toString(AlignFailure failure) {
  switch (failure) {
    case AlignFailure::none: return "none";
    case AlignFailure::no_data: return "no_data";
    case AlignFailure::too_few_inliers: return "too_few_inliers";
    case AlignFailure::degenerate: return "degenerate";
    case AlignFailure::gate: return "correction_gate";
  }
  return "unknown";
}

std::string describeCues(const std::vector<CueStats>& cues) {
  std::string out;
  for (const CueStats& c : cues) {
    const size_t dot = c.slice.rfind('.');
    out += (out.empty() ? "" : "; ") + (dot == std::string::npos ? c.slice : c.slice.substr(dot + 1));
    out += ": " + std::to_string(c.inliers) + (c.inliers == 1 ? " inlier of " : " inliers of ") +
           std::to_string(c.factors) + (c.factors == 1 ? " factor" : " factors");
    if (c.candidates) out += ", " + std::to_string(c.candidates) + " candidates";
  }
  return out;
}

namespace {

// Binds a slice's or seeder's entries: raw and measurement ones to the frame, scene ones to the
// scene. False when one is absent.
bool bindEntries(const std::vector<EntryBase*>& entries, const Frame& frame,
                 const PropertyContainer& scene) {
  bool present = true;
  for (EntryBase* entry : entries) {
    const Container c = entry->container();
    entry->bind(c == Container::scene ? &scene : c == Container::raw ? &frame.raw
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
AlignSeeder<S>::~AlignSeeder() = default;

template <class S>
std::vector<typename S::Pose> AlignSeeder<S>::seeds(const Frame& frame,
                                                    const PropertyContainer& scene,
                                                    const AlignContext<S>& context) {
  if (!bindEntries(entries(), frame, scene)) return {};
  return search(ofFrame(context, frame));
}

template <class S>
MultiAligner<S>::MultiAligner() = default;
template <class S>
MultiAligner<S>::~MultiAligner() = default;

template <class S>
void MultiAligner<S>::configure() {
  for (double h : retry_headings())
    if (!(std::abs(h) <= M_PI))
      throw ParamError("retry_headings",
                       "every value must be an angle in [-pi, pi] rad, got " + std::to_string(h));
  if (seed_tolerance().size() != 2)
    throw ParamError("seed_tolerance", "expected 2 values (translation m, rotation rad), got " +
                                           std::to_string(seed_tolerance().size()));
  for (double v : seed_tolerance())
    if (!(v > 0)) throw ParamError("seed_tolerance", "every value must be > 0");
}

template <class S>
AlignResult<S> MultiAligner<S>::align(const Frame& frame, const PropertyContainer& scene,
                                      const AlignContext<S>& context) {
  std::vector<AlignerSlice<S>*> active;
  for (auto& slice : slices)
    if (slice->bind(frame, scene, context)) active.push_back(slice.get());
  if (active.empty()) {
    AlignResult<S> none;
    none.pose = context.guess;
    none.H.setZero();
    return none;
  }
  AlignResult<S> result = solve(active, context.guess);
  if (result.valid) return result;
  // The last tangent coordinate is the rotation about the vertical axis in 2D and 3D alike.
  for (double heading : retry_headings()) {
    typename S::Vector turn = S::Vector::Zero();
    turn(S::kDof - 1) = heading;
    AlignResult<S> retry = solve(active, S::boxplus(context.guess, turn));
    if (retry.valid && (!result.valid || retry.inliers > result.inliers)) result = retry;
  }
  if (!result.valid && relocalise()) {
    // Wide-baseline recovery: a slice that can place the robot from its cue alone proposes a
    // pose, and the ordinary solve (every slice) refines it.
    for (AlignerSlice<S>* slice : active) {
      auto* recoverable = dynamic_cast<RecoverableSlice<S>*>(slice);
      if (!recoverable) continue;
      const std::optional<Pose> proposed = recoverable->recoverPose();
      if (!proposed) continue;
      AlignResult<S> retry = solve(active, *proposed);
      if (retry.valid && (!result.valid || retry.inliers > result.inliers)) result = retry;
    }
  }
  if (result.valid || !seeder) return result;
  AlignResult<S> seeded = recoverBound(frame, scene, context, active);
  seeded.unseeded_inliers = result.inliers;  // the caller weighs the seed against it
  return seeded.valid ? seeded : result;
}

template <class S>
AlignResult<S> MultiAligner<S>::recover(const Frame& frame, const PropertyContainer& scene,
                                        const AlignContext<S>& context) {
  AlignResult<S> none;
  none.pose = context.guess;
  none.H.setZero();
  if (!seeder) return none;
  std::vector<AlignerSlice<S>*> active;
  for (auto& slice : slices)
    if (slice->bind(frame, scene, context)) active.push_back(slice.get());
  if (active.empty()) return none;
  return recoverBound(frame, scene, context, active);
}

template <class S>
AlignResult<S> MultiAligner<S>::recoverBound(const Frame& frame, const PropertyContainer& scene,
                                             const AlignContext<S>& context,
                                             const std::vector<AlignerSlice<S>*>& active) {
  AlignResult<S> best;
  best.pose = context.guess;
  best.H.setZero();
  // A solve that leaves its seed by more than the seeder's resolution slid off what the search
  // found (along a corridor, onto a parallel wall): it does not count.
  for (const Pose& seed : seeder->seeds(frame, scene, context)) {
    AlignResult<S> r = solve(active, seed);
    const Pose moved = S::normalized(seed.inverse() * r.pose);
    r.seeded = true;
    if (r.valid && (S::distance(moved) > seed_tolerance()[0] ||
                    S::angle(moved) > seed_tolerance()[1])) {
      r.valid = false;
      r.failure = AlignFailure::gate;
    }
    if (r.valid && (!best.valid || r.inliers > best.inliers)) best = r;
    if (!best.valid && !r.valid && r.failure != AlignFailure::no_data) best = r;
  }
  return best;
}

template <class S>
AlignResult<S> MultiAligner<S>::solve(const std::vector<AlignerSlice<S>*>& active,
                                      const Pose& guess) {
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
  };
  typename S::Pose t = guess;
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
  } else if (!(eig.eigenvalues().minCoeff() >
               1e-9 * std::max(1.0, eig.eigenvalues().maxCoeff()))) {
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
template class AlignSeeder<Space2D>;
template class AlignSeeder<Space3D>;
template class RecoverableSlice<Space2D>;
template class RecoverableSlice<Space3D>;
template class MultiAligner<Space2D>;
template class MultiAligner<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
