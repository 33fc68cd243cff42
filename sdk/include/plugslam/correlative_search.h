#pragma once
// Correlative search (Olson, "Real-time correlative scan matching", ICRA 2009; Hess et al.,
// "Real-time loop closure in 2D LIDAR SLAM", ICRA 2016): the Multi-Aligner's first step. The
// robot's pose is searched on a lattice of planar poses around the prediction, as wide as the
// motion prior's uncertainty; every slice that can (ScoringSlice) scores each lattice pose and
// the scores add up, so two lasers search together. Branch and bound over coarser levels (a
// level-h node stands for 2^h x 2^h translations, bounded from above by every scorer) finds the
// best pose exactly without scoring them all; a second search outside the best pose's
// neighbourhood says whether another pose scores nearly as well (a corridor, a look-alike).
#include <vector>

#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// The candidate poses of a search: the center turned by a heading step and moved by whole
/// cells in the scene's x-y plane.
template <class S>
struct SearchLattice {
  typename S::Pose center = S::Pose::Identity();  ///< the prediction (scene <- robot)
  double resolution = 0.05;                       ///< [m] translation step
  double angular_step = 0.01;                     ///< [rad] heading step
  int cells = 0;                                  ///< translations -cells..cells (in x and y)
  int angles = 0;                                 ///< headings -angles..angles
  int levels = 0;  ///< coarser levels above the base (level h: 2^h x 2^h cells a node)
  /// The pose at heading index a and cell offsets (x, y).
  typename S::Pose pose(int a, int x, int y) const;
  /// The indices (a, x, y) of the lattice pose nearest `p`; false when it lies outside.
  bool nearest(const typename S::Pose& p, int& a, int& x, int& y) const;
};

/// Scores lattice poses. Scores are sums of per-element values in [0, 1] (a point on the map
/// scores 1), so scorers of different sizes add up as one measurement.
class LatticeScorer {
 public:
  virtual ~LatticeScorer();
  /// At level 0 the score of pose (a, x, y); at level h an upper bound of the scores of the
  /// poses (a, x..x+2^h-1, y..y+2^h-1).
  virtual double score(int level, int a, int x, int y) const = 0;
  /// The most score() can give (the number of elements scored).
  virtual double maxScore() const = 0;
};

/// Optional second base of an aligner slice whose cue can score lattice poses against the
/// scene (the laser's correlative match); the Multi-Aligner searches with every such slice.
template <class S>
class ScoringSlice : public LatticeScorer {
 public:
  ~ScoringSlice() override;
  /// The heading step [rad] that moves the cue's farthest element by one `resolution` cell.
  virtual double angularStep(double resolution) const = 0;
  /// Prepares to score `lattice` (after bind); false: the slice cannot score this frame.
  virtual bool beginSearch(const SearchLattice<S>& lattice) = 0;
};

/// Options of correlativeSearch.
struct SearchOptions {
  double min_score = 0.3;             ///< the best pose's normalized score must reach this
  double ambiguity_margin = 0.03;     ///< a distinct pose within this of the best is a rival
  double distinct_translation = 0.5;  ///< [m] poses farther apart than this are distinct...
  double distinct_rotation = 0.2;     ///< [rad] ...or turned more than this
  /// The motion prior in the score (Olson's posterior, with a broad floor): a pose m standard
  /// deviations of the prior from the lattice's center loses prior_margin x min(m^2, prior_cap)
  /// / prior_cap of normalized score. 0: the scores alone decide.
  double prior_margin = 0;
  double prior_translation = 0;  ///< [1/m^2] the prior's information in translation (per axis)
  double prior_rotation = 0;     ///< [1/rad^2] its information in heading
  double prior_cap = 9;          ///< m^2 from which on the penalty stays the same
};

/// Outcome of a correlative search.
template <class S>
struct SearchResult {
  bool found = false;      ///< a pose reached min_score
  bool ambiguous = false;  ///< a distinct pose scored within the margin of the best
  typename S::Pose pose = S::Pose::Identity();   ///< the best pose
  typename S::Pose rival = S::Pose::Identity();  ///< the distinct pose, when ambiguous
  double score = 0;                              ///< of the best pose, normalized (0..1)
  double rival_score = 0;                        ///< of the rival, when ambiguous
  int leaves = 0;                                ///< poses scored at level 0 (the search's effort)
};

/// The best pose of `lattice` by the summed scores of `scorers` (each prepared for it).
template <class S>
SearchResult<S> correlativeSearch(const std::vector<const LatticeScorer*>& scorers,
                                  const SearchLattice<S>& lattice, const SearchOptions& options);

/// The summed, normalized score of lattice pose (a, x, y).
double latticeScore(const std::vector<const LatticeScorer*>& scorers, int a, int x, int y);

/// Coarser levels a search of +-`cells` needs so that its top level covers the window.
int searchLevels(int cells, int max_levels = 16);

extern template struct SearchLattice<Space2D>;
extern template struct SearchLattice<Space3D>;
extern template class ScoringSlice<Space2D>;
extern template class ScoringSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
