#pragma once
// The Multi-Aligner (seed, section IV-B): one iterative least-squares solve on the robot's
// relative pose, to which every slice adds the factors of its cue. Data association is redone
// at each outer iteration; each inner iteration is a damped Gauss-Newton step.
// Before it, when the prediction comes with a covariance, a correlative search over the window
// that covariance sets (correlative_search.h: every slice that can score poses takes part) picks
// where the solve starts; the prediction enters the solve as a factor with the same covariance;
// a search that finds a rival pose nearly as good marks the result ambiguous and takes the
// information along the rival's direction down to what the two poses leave known.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "plugslam/align_failure.h"
#include "plugslam/aligner_slice.h"
#include "plugslam/correlative_search.h"

namespace plugslam {
inline namespace abi_v1 {

/// One slice's share of an alignment, counted by the SDK at the solution.
struct CueStats {
  std::string slice;      ///< the slice's instance name
  size_t factors = 0;     ///< factors it added
  size_t inliers = 0;     ///< of them within its inlier band
  size_t candidates = 0;  ///< measurement elements it tried to associate (0: not known)
  /// inliers / factors, 0 without factors.
  double inlierRatio() const { return factors ? double(inliers) / factors : 0.0; }
  /// inliers / candidates: how much of the cue the scene explains (0 when unknown).
  double overlap() const { return candidates ? double(inliers) / candidates : 0.0; }
};

/// "slices[0]: 412 inliers of 430 factors, 541 candidates; slices[1]: 1 inlier of 1 factor":
/// per-slice counts for messages (a slice is named by the last part of its instance name).
std::string describeCues(const std::vector<CueStats>& cues);

/// Outcome of one alignment.
template <class S>
struct AlignResult {
  typename S::Pose pose;       ///< estimate of the robot in the scene frame
  typename S::Matrix H;        ///< information of the estimate (J^T W J at the solution)
  double chi2 = 0;             ///< final robustified error
  size_t inliers = 0;          ///< inlier factors at the solution
  size_t factors = 0;          ///< factors at the solution
  size_t candidates = 0;       ///< measurement elements considered, summed over the cues
  int iterations = 0;          ///< Gauss-Newton steps taken
  bool converged = false;      ///< the step fell below the threshold
  bool valid = false;          ///< enough constraints for a well-posed solution
  std::vector<CueStats> cues;  ///< per slice that took part, in slice order
  /// Why the result is not valid (none when it is); the aligner sets all but `gate`.
  AlignFailure failure = AlignFailure::no_data;
  /// With `degenerate`: the unit direction (tangent coordinates) the information constrains
  /// least, e.g. along a corridor's axis.
  typename S::Vector weakest = S::Vector::Zero();
  /// The correlative search found a pose and the solve started from it.
  bool searched = false;
  double search_score = 0;  ///< the searched pose's normalized score (0..1)
  /// A distinct pose scored nearly as well as the chosen one: H holds no more along `rival`
  /// than the two poses leave known.
  bool ambiguous = false;
  /// With `ambiguous`: the rival pose as a tangent vector at `pose` (robot frame).
  typename S::Vector rival = S::Vector::Zero();
  /// The pose came from another hypothesis than the prediction's mean (a cue's recoverPose(),
  /// or the pace kept through a gap in the stamps), which explained more than the solve from it.
  bool hypothesis = false;
  /// The solve could not vouch for its motion (the data barely measure the step along the
  /// direction of travel, or the prediction was beyond the cues' reach) and no hypothesis
  /// without the prediction could be made to check it: the pose may be wrong.
  bool unchecked = false;
  double search_s = 0;  ///< [s] spent searching
  double refine_s = 0;  ///< [s] spent in the solve
  /// Valid, unambiguous and vouched for: the data fixed the step, so it tells how far the
  /// prediction was off (MotionPrediction::solved).
  bool fixesStep() const { return valid && !ambiguous && !unchecked; }
  /// inliers / factors, 0 without factors.
  double inlierRatio() const { return factors ? double(inliers) / factors : 0.0; }
  /// How much of the measurement the scene explains: inliers over candidates, summed over the
  /// cues that count their candidates (a cue that does not, such as a motion prior, has no say);
  /// 0 when none does.
  double overlap() const {
    size_t in = 0, of = 0;
    for (const CueStats& c : cues)
      if (c.candidates) {
        in += c.inliers;
        of += c.candidates;
      }
    return of ? double(in) / of : 0.0;
  }
};

/// Aligns a measurement to a scene with any number of slices ("sdk.MultiAligner2D/3D").
template <class S>
class MultiAligner : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "Aligner2D" : "Aligner3D";
  using Pose = typename S::Pose;
  MultiAligner();
  ~MultiAligner() override;

  SlotList<AlignerSlice<S>> slices{this, "slices", "one per cue; all factors go in one solve"};
  Param<int> outer_iterations{this, "outer_iterations",        10,
                              "",   "data association rounds", Range{1, 1000}};
  Param<int> inner_iterations{
      this, "inner_iterations", 3, "", "Gauss-Newton steps per association round", Range{1, 100}};
  Param<double> convergence{
      this, "convergence", 1e-5, "", "stop when the step's norm falls below this", Range{0, 1}};
  Param<double> damping{
      this, "damping", 1e-6, "", "Levenberg damping added to the diagonal", Range{0, 1e6}};
  Param<int> min_inliers{
      this,         "min_inliers", 10, "", "fewer inliers than this makes the result invalid",
      Range{0, 1e9}};
  // Relocalisation by a cue's own means (the landmark cue: descriptor matching + RANSAC)
  // when the solve fails.
  Param<bool> relocalise{this, "relocalise", true, "",
                         "when the alignment is invalid, solve again from the pose each slice "
                         "that can relocalise without a prior proposes (the landmark cue: "
                         "descriptor matching + RANSAC)"};

  // The search window is the prediction's uncertainty: this many standard deviations cover all
  // but the rarest errors of a gaussian motion model.
  Param<double> search_sigmas{this,
                              "search_sigmas",
                              3.0,
                              "",
                              "half-width of the correlative search in standard deviations of "
                              "the prediction (0: no search)",
                              Range{0, 100}};
  // A scan sees a local map only within its range: a wider window finds nothing the map can
  // confirm, only look-alikes, and costs time.
  Param<std::vector<double>> max_window{
      this,
      "max_window",
      {3.0, M_PI},
      "m, rad",
      "largest half-width of the search (translation, rotation) whatever the uncertainty"};
  // The search need only land the solve within its basin of convergence (a few association
  // gates' worth); the solve gives the precision. A coarser lattice is cheaper to rasterize.
  Param<double> search_resolution{this,
                                  "search_resolution",
                                  0.1,
                                  "m",
                                  "translation step of the search (the scoring cues' grid cell)",
                                  Range{1e-3, 10}};
  Param<double> min_score{this,
                          "min_score",
                          0.3,
                          "",
                          "the searched pose's normalized score must reach this, else the solve "
                          "starts from the prediction (after a step the scan sees much that the "
                          "local map never did)",
                          Range{0, 1}};
  // The prediction's typical error, where the run measured it (AlignContext::typical), is a
  // prior on the searched pose (Olson's posterior): near look-alikes (a corridor's next door, a
  // turned room) lose to the pose the motion expects unless they fit clearly better. Beyond search_sigmas of the typical error the penalty stops
  // growing: there only the motion's bound (the window) holds, and a pose that fits this much
  // better still wins, so a sudden change of pace is found rather than forced to the prediction.
  Param<double> prior_margin{this,
                             "prior_margin",
                             0.1,
                             "",
                             "normalized score a pose beyond search_sigmas of the prediction's "
                             "typical error must gain over one at the prediction to win the "
                             "search (0: the scores alone decide)",
                             Range{0, 1}};
  Param<double> ambiguity_margin{this,
                                 "ambiguity_margin",
                                 0.03,
                                 "",
                                 "a distinct pose scoring within this of the best is a rival: "
                                 "the result is ambiguous",
                                 Range{0, 1}};
  // Also the check of the solve: one from the searched pose that ends a distinct peak away from
  // it went to a minimum the search did not find best (a corridor's slide, a wall pair's swap).
  Param<std::vector<double>> distinct{
      this,
      "distinct",
      {0.5, 0.2},
      "m, rad",
      "poses farther apart than this (translation or rotation) are distinct peaks of the "
      "search, not one peak's spread; a solve that ends this far from the searched pose slid "
      "off it and is invalid"};
  // A solve from the prediction that converged is not yet a measurement of the motion: points
  // that cannot see the step (far ones, along the direction of travel) agree with any nearby
  // pose. It counts as measured when the data alone know the step to this fraction (3 sigma),
  // or twice as well as the prediction did.
  Param<double> step_tolerance{this,
                               "step_tolerance",
                               0.05,
                               "",
                               "fraction of the step the solve must measure along the direction "
                               "of travel (3 sigma) unless it beats the prediction's uncertainty "
                               "by half; a solve that does neither is checked against a "
                               "hypothesis made without the prediction (cues that can make one)",
                               Range{0, 10}};
  Param<bool> motion_prior{this, "motion_prior", S::kDim == 2, "",
                           "add the prediction to the solve as a factor with its covariance "
                           "(the motion model's, or constant velocity's)"};

  void configure() override;
  /// Aligns the frame's cues to the scene: searches the window context.covariance sets (when
  /// given and a slice can score), then solves from the searched pose, or from context.guess,
  /// with the prediction as a factor (motion_prior); relocalises while the result is invalid.
  AlignResult<S> align(const Frame& frame, const PropertyContainer& scene,
                       const AlignContext<S>& context);

 private:
  // The search window (translation m, rotation rad) a prediction's covariance sets.
  std::pair<double, double> window(const typename S::Matrix& covariance) const;
  // The correlative search of `window` around `guess` with `scorers`, favouring poses near it
  // by `prior` (the covariance of its typical error; none: the scores alone); the lattice and
  // the scorers that took part are kept in `lattice` and `ready`.
  SearchResult<S> search(const std::vector<ScoringSlice<S>*>& scorers, const Pose& guess,
                         const typename S::Matrix* prior, std::pair<double, double> window,
                         SearchLattice<S>& lattice, std::vector<const LatticeScorer*>& ready);
  // Invalidates `result` (slid) when the solve from the searched pose `start` left it for
  // another peak, or left the window without a wider search confirming it.
  void check(const std::vector<ScoringSlice<S>*>& scorers, const Pose& guess,
             const typename S::Matrix* prior, const Pose& start, const SearchLattice<S>& lattice,
             AlignResult<S>& result);
  // Whether `pose` lies within the window the prediction's covariance sets (search_sigmas).
  bool withinWindow(const AlignContext<S>& context, const Pose& pose) const;
  // Whether the data in `result` (without the prediction's factor `prior_information`) measure
  // the motion from context.previous along the direction of travel (step_tolerance).
  bool motionMeasured(const AlignContext<S>& context, const AlignResult<S>& result,
                      const typename S::Matrix* prior_information) const;
  // One solve from `start` with the slices already bound (`prior`: the prediction's factor).
  AlignResult<S> solve(const std::vector<AlignerSlice<S>*>& active, const Pose& start,
                       const Pose* prior_mean, const typename S::Matrix* prior_information);
};

extern template class MultiAligner<Space2D>;
extern template class MultiAligner<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
