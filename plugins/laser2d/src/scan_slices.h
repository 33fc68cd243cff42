#pragma once
// Aligner slices of the laser2d cue: point-to-line and point-to-point ICP factors between the
// measured cloud (robot frame) and the scene cloud (local-map frame). Both share one base that
// declares the entries, keeps the search index and does the data association; the factors are
// the SDK's (solver/registration_factors.h), added through NormalEquations::add.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "correlative_matcher.h"
#include "plugslam/aligner_slice.h"
#include "plugslam/correlative_search.h"
#include "plugslam/solver/robust_kernel.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Entries, nearest-neighbour association (k-d tree or projective) and the robust weighting
/// shared by the laser2d aligner slices, and the correlative score of the scan against a
/// likelihood grid of the scene that the Multi-Aligner's search sums (ScoringSlice).
class ScanSliceBase : public AlignerSlice<Space2D>, public ScoringSlice<Space2D> {
 public:
  Input<PointCloud2D> measurement{this, Container::measurement, "measurement", "front",
                                  "measured cloud to align (robot frame)"};
  Input<PointCloud2D> scene{this, Container::scene, "scene", "front",
                            "local map's cloud to align against"};
  Param<double> max_distance{this, "max_distance", 0.5, "m", "association gate", Range{1e-6, 100}};
  Param<std::string> association{this,
                                 "association",
                                 "kdtree",
                                 "",
                                 "nearest neighbour in a k-d tree of the scene, or projective "
                                 "(scene binned by bearing from the robot)",
                                 Choices{{"kdtree", "projective"}}};
  Param<std::string> kernel{this, "kernel",        "cauchy",
                            "",   "robust kernel", Choices{{"none", "huber", "cauchy", "tukey"}}};
  Param<double> kernel_scale{this,
                             "kernel_scale",
                             0.1,
                             "m",
                             "kernel scale, and the residual below which a pair is an inlier",
                             Range{1e-6, 100}};
  Param<double> sigma{
      this, "sigma", 0.02, "m", "range noise; each pair weighs 1/sigma^2", Range{1e-6, 100}};
  // A far point's line fit and its nearest scene point are one beam spacing (range x angular
  // resolution) apart, so its point-to-line error grows with range: in big halls the far points'
  // errors would otherwise fail the validators' residual check of right loops. The kernel works
  // in units of each pair's sigma, so those larger errors are not taken for outliers.
  Param<double> range_sigma{this,
                            "range_sigma",
                            0.0,
                            "",
                            "noise growth with range: a pair's sigma is hypot(sigma, range_sigma "
                            "x the measured point's range) (0: sigma for every pair)",
                            Range{0, 1}};
  Param<double> max_normal_angle{this,
                                 "max_normal_angle",
                                 0.8,
                                 "rad",
                                 "reject pairs whose normals differ more than this (pi: off)",
                                 Range{0, M_PI}};
  // A point past the end of the scene's surface (a door gap, a wall's end) is paired with the
  // surface's last point, and point-to-line extrapolates that line to it: a wrong factor that
  // slides corridors along their axis. Beam spacing stays below this out to ~20 m at 0.5 deg.
  Param<double> max_tangential{this,
                               "max_tangential",
                               0.2,
                               "m",
                               "reject pairs offset along the scene point's line by more (0: off)",
                               Range{0, 100}};
  Param<double> projective_resolution{this,
                                      "projective_resolution",
                                      0.25 * M_PI / 180,
                                      "rad",
                                      "bearing bin width of the projective association",
                                      Range{1e-4, 0.5}};

  // The search's heading step moves the farthest scored point by one cell: far points cost
  // fine steps over the whole angular window, and beyond a few tens of metres a scan's points
  // are too sparse to score a cell anyway (the solve still uses them).
  Param<double> search_range{this,
                             "search_range",
                             30.0,
                             "m",
                             "the correlative search scores the scan's points within this range",
                             Range{0.1, 1000}};
  // A far wall's points are a beam spacing apart, wider than a cell: each stands for a patch of
  // its wall so that the gaps between them still score.
  Param<double> point_extent{this,
                             "point_extent",
                             0.1,
                             "m",
                             "in the search's grid each scene point covers this much of its "
                             "wall either side (along its tangent)",
                             Range{0, 10}};

  ScanSliceBase();
  ~ScanSliceBase() override;
  void configure() override;
  void associate(const Pose& t) override;
  double angularStep(double resolution) const override;
  bool beginSearch(const SearchLattice<Space2D>& lattice) override;
  double score(int level, int a, int x, int y) const override {
    return scorer_->score(level, a, x, y);
  }
  double maxScore() const override { return scorer_ ? scorer_->maxScore() : 0.0; }

  /// The pairs (measured index, scene index) of the last association.
  const std::vector<std::pair<int, int>>& pairs() const { return pairs_; }
  /// How many times the k-d tree was built (a scene left unchanged is not rebuilt).
  size_t treeBuilds() const { return tree_builds_; }

 protected:
  bool prepare(const AlignContext<Space2D>& context) override;
  /// The kernel (in units of each pair's sigma) and the inlier band (kernel_scale, in metres).
  Robust robust() const { return Robust{kernel_.get(), kernel_scale()}; }

  std::vector<std::pair<int, int>> pairs_;
  double information_ = 1.0;  // 1 / sigma^2
  /// Information 1 / sigma_i^2 of measured point i (information_ unless range_sigma > 0).
  double informationOf(int i) const {
    return point_information_.empty() ? information_ : point_information_[i];
  }
  std::vector<double> point_information_;
  std::unique_ptr<RobustKernel> kernel_;

 private:
  void associateKdTree(const Pose& t);
  void associateProjective(const Pose& t);
  void accept(int i, int j, const Eigen::Vector2d& point_in_scene,
              const Eigen::Vector2d& normal_in_scene);

  struct KdTree;
  std::unique_ptr<KdTree> tree_;
  double search_extent_ = 0;               // the farthest measured point within search_range [m]
  std::unique_ptr<CorrelativeGrid> grid_;  // of the scene, for the current search
  std::unique_ptr<GridScorer> scorer_;
  uint64_t tree_revision_ = 0;
  size_t tree_builds_ = 0;
  double cos_normal_ = -1.0;
  // The parameter values the cached information, kernel and normal gate were made from.
  std::string made_kernel_;
  double made_scale_ = -1, made_sigma_ = -1, made_normal_angle_ = -1;
  // Projective association: per bearing bin, the nearest scene point (index, range).
  std::vector<int> bin_index_;
  std::vector<double> bin_range_;
};

/// laser2d.PointToLineSlice: e = n_q^T (T p - q) (PointToLine2D), one scalar factor per pair.
class PointToLineSlice final : public ScanSliceBase {
 public:
  void linearize(const Pose& t, NormalEquations<Space2D>& eq) const override;
};

/// laser2d.PointToPointSlice: e = T p - q (PointToPoint2D), one 2D factor per pair.
class PointToPointSlice final : public ScanSliceBase {
 public:
  void linearize(const Pose& t, NormalEquations<Space2D>& eq) const override;
};

}  // namespace laser2d
}  // namespace plugslam
