#pragma once
// laser2d.CorrelativeValidator: loop closures validated by the correlative scan-to-map matcher
// (correlative_matcher.h), which finds them under drift too large for a local aligner.
#include <string>

#include "correlative_matcher.h"
#include "plugslam/entry.h"
#include "plugslam/geometry.h"
#include "plugslam/loop_closure.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Loop validator by correlative scan-to-map matching ("laser2d.CorrelativeValidator"). Put it
/// first in the chain: it finds the closure under large drift, a fine aligner refines it.
class CorrelativeValidator final : public LoopValidator {
 public:
  Input<PointCloud2D> scene{this, Container::scene, "scene", "front", "local maps' cloud to match"};
  Param<double> resolution{this, "resolution", 0.05, "m", "grid cell", Range{1e-3, 10}};
  Param<double> search_window{this,
                              "search_window",
                              6.0,
                              "m",
                              "half-width of the translation window around the guess (x and y)",
                              Range{0, 100}};
  Param<double> angular_window{this,
                               "angular_window",
                               0.6,
                               "rad",
                               "half-width of the rotation window around the guess",
                               Range{0, 3.2}};
  Param<double> angular_step{this,
                             "angular_step",
                             0.0,
                             "rad",
                             "rotation step; 0: one cell of arc at the query's farthest point",
                             Range{0, 1}};
  Param<double> min_score{this,
                          "min_score",
                          0.55,
                          "",
                          "mean likelihood of the query's points on the candidate's grid",
                          Range{0, 1}};
  Param<double> min_score_margin{this,
                                 "min_score_margin",
                                 0.03,
                                 "",
                                 "the best pose must beat any distinct pose by this much "
                                 "(rejects ambiguous places such as corridors)",
                                 Range{0, 1}};
  Param<double> distinct_translation{
      this,         "distinct_translation", 0.5, "m", "poses farther apart than this are distinct",
      Range{0, 100}};
  Param<double> distinct_rotation{
      this,         "distinct_rotation", 0.2, "rad", "poses rotated more than this are distinct",
      Range{0, 3.2}};
  Param<double> point_extent{this,
                             "point_extent",
                             0.1,
                             "m",
                             "each candidate point covers this much wall either side along its "
                             "tangent (fills the gaps between sparse far points)",
                             Range{0, 10}};
  Param<double> max_range{this,
                          "max_range",
                          30.0,
                          "m",
                          "query points farther than this from the query's origin are ignored "
                          "(bounds the grid and the angular step)",
                          Range{0.1, 1e4}};

  bool validate(const LocalMap& candidate, const LocalMap& query, const Eigen::Isometry3d& guess,
                LoopClosure& closure, std::string& reason) override;
};

}  // namespace laser2d
}  // namespace plugslam
