#pragma once
// The Multi-Aligner (seed, section IV-B): one iterative least-squares solve on the robot's
// relative pose, to which every slice adds the factors of its cue. Data association is redone
// at each outer iteration; each inner iteration is a damped Gauss-Newton step.
#include <string>
#include <vector>

#include "plugslam/align_failure.h"
#include "plugslam/align_seeder.h"
#include "plugslam/aligner_slice.h"

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
  typename S::Pose pose;         ///< estimate of the robot in the scene frame
  typename S::Matrix H;          ///< information of the estimate (J^T W J at the solution)
  double chi2 = 0;               ///< final robustified error
  size_t inliers = 0;            ///< inlier factors at the solution
  size_t factors = 0;            ///< factors at the solution
  size_t candidates = 0;         ///< measurement elements considered, summed over the cues
  int iterations = 0;            ///< Gauss-Newton steps taken
  bool converged = false;        ///< the step fell below the threshold
  bool valid = false;            ///< enough constraints for a well-posed solution
  std::vector<CueStats> cues;    ///< per slice that took part, in slice order
  /// Why the result is not valid (none when it is); the aligner sets all but `gate`.
  AlignFailure failure = AlignFailure::no_data;
  /// With `degenerate`: the unit direction (tangent coordinates) the information constrains
  /// least, e.g. along a corridor's axis.
  typename S::Vector weakest = S::Vector::Zero();
  /// The solve started from a seeder's pose (MultiAligner::seeder), not the prediction.
  bool seeded = false;
  /// With `seeded` from align(): the inliers of the best solve from the prediction (and the
  /// retry headings) that failed, which the seed's solve replaced.
  size_t unseeded_inliers = 0;
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
  Param<int> outer_iterations{this, "outer_iterations", 10, "",
                              "data association rounds", Range{1, 1000}};
  Param<int> inner_iterations{this, "inner_iterations", 3, "",
                              "Gauss-Newton steps per association round", Range{1, 100}};
  Param<double> convergence{this, "convergence", 1e-5, "",
                            "stop when the step's norm falls below this", Range{0, 1}};
  Param<double> damping{this, "damping", 1e-6, "",
                        "Levenberg damping added to the diagonal", Range{0, 1e6}};
  Param<int> min_inliers{this, "min_inliers", 10, "",
                         "fewer inliers than this makes the result invalid", Range{0, 1e9}};
  // A heading error of the prediction moves far points more than the association gate (0.1 rad
  // at 10 m is 1 m): no pairs form and the solve cannot start. Restarting from turned guesses is
  // a one-dimensional search in the direction odometry knows worst; it costs nothing on frames
  // that align from the prediction.
  Param<std::vector<double>> retry_headings{
      this, "retry_headings", {}, "rad",
      "when the alignment from the prediction is invalid, retry from the prediction turned by "
      "each of these about the vertical axis; the valid result with the most inliers wins"};

  // Two sources of other starting poses, tried in this order while the result is invalid: slices
  // that relocalise from their own cue without a prior (RecoverableSlice: the landmark cue's
  // descriptor matching + RANSAC, issue 15), then the seeder's search in a window around the
  // prediction (AlignSeeder: the laser's correlative search, issue 20).
  Param<bool> relocalise{this, "relocalise", true, "",
                         "when the alignment from the prediction (and the retry headings) is "
                         "invalid, solve again from the pose each slice that can relocalise "
                         "without a prior proposes (the landmark cue: descriptor matching + "
                         "RANSAC)"};

  // Recovery from a poor prediction (issue 20): a search over a wide window proposes where to
  // start when the solve from the prediction fails (or, asked by the tracker, when it lands too
  // far from the prediction).
  Slot<AlignSeeder<S>> seeder{this, "seeder", "",
                              "searches the scene for starting poses when the solve from the "
                              "prediction fails (e.g. laser2d.CorrelativeSeeder; empty: none)"};
  Param<std::vector<double>> seed_tolerance{
      this, "seed_tolerance", {0.2, 0.1}, "m, rad",
      "translation and rotation: a solve from a seed that ends farther than this from it slid "
      "off what the search found and does not count"};

  void configure() override;
  /// Aligns the frame's cues to the scene, starting from context.guess (then from the retry
  /// headings, then from the relocalising slices' and the seeder's poses, while the result is
  /// invalid).
  AlignResult<S> align(const Frame& frame, const PropertyContainer& scene,
                       const AlignContext<S>& context);
  /// Aligns from the seeder's poses only (none: an invalid result); the valid solve with the
  /// most inliers wins.
  AlignResult<S> recover(const Frame& frame, const PropertyContainer& scene,
                         const AlignContext<S>& context);

 private:
  AlignResult<S> recoverBound(const Frame& frame, const PropertyContainer& scene,
                              const AlignContext<S>& context,
                              const std::vector<AlignerSlice<S>*>& active);
  // One solve from `guess` with the slices already bound.
  AlignResult<S> solve(const std::vector<AlignerSlice<S>*>& active, const Pose& guess);
};

extern template class MultiAligner<Space2D>;
extern template class MultiAligner<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
