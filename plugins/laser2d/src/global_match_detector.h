#pragma once
// laser2d.GlobalMatchDetector: loop detection after large drift (issue 5). The query map's
// points are matched against a grid of each candidate's neighbourhood over a wide window of
// translations and rotations by branch and bound, as Cartographer's fast correlative scan
// matcher does (Hess et al., ICRA 2016); the best pose is handed to the validators.
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <string>
#include <vector>

#include "correlative_matcher.h"
#include "plugslam/drift_gate.h"
#include "plugslam/entry.h"
#include "plugslam/loop_closure.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// A candidate's neighbourhood rasterized for matching: hits blurred over a cell, cells crossed
/// by rays free (0), cells no ray reached `unknown`; and which cells were observed.
struct MatchGrid {
  std::unique_ptr<CorrelativeGrid> grid;  ///< the scores and their pooled levels
  std::vector<uint8_t> observed;          ///< 1 where a ray or a hit reached the cell (base)
  /// True when cell (x, y) of the base was observed.
  bool isObserved(int x, int y) const {
    if (x < 0 || y < 0 || x >= grid->width() || y >= grid->height()) return false;
    return observed[static_cast<size_t>(y) * grid->width() + x] != 0;
  }
};

/// Cloud of one local map placed in the grid's frame: its origin and its points with normals.
struct PlacedCloud {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();  ///< where the rays start (the map origin)
  std::vector<Eigen::Vector2d> points;               ///< in the grid's frame
  std::vector<Eigen::Vector2d> normals;              ///< one per point
};

/// Rasterizes clouds at `resolution` with `levels` pooled levels. Hits score 255 with a
/// gaussian fall-off of one cell (each point also covers one cell along its tangent); cells a
/// ray crossed score 0; unobserved cells (and the outside) score `unknown` (0..255).
MatchGrid rasterizeClouds(const std::vector<PlacedCloud>& clouds, double resolution, int levels,
                          uint8_t unknown);

/// The clouds (entry `scene`) of maps `ids`, each without its points beyond `max_range` of its
/// origin, placed by `place(id)`: the map's frame in the grid's.
std::vector<PlacedCloud> placeClouds(const GraphView& view, const Input<PointCloud2D>& scene,
                                     const std::vector<int64_t>& ids, double max_range,
                                     const std::function<SE2(int64_t)>& place);

/// Loop detector by global scan-to-map matching ("laser2d.GlobalMatchDetector"): for maps
/// within a drift-grown radius, matches the query's points against the candidate's
/// neighbourhood over a window as wide as that radius, and proposes the best pose found.
class GlobalMatchDetector final : public LoopDetector {
 public:
  Input<PointCloud2D> scene{this, Container::scene, "scene", "front", "local maps' cloud to match"};
  Param<double> resolution{this, "resolution", 0.1, "m", "grid cell of the search",
                           Range{0.01, 1}};
  Param<double> radius{this, "radius", 5.0, "m",
                       "search radius (and window half-width) with no drift", Range{0, 1e4}};
  Param<double> drift{this, "drift", 0.2, "",
                      "radius grows by this fraction of the path travelled since the candidate",
                      Range{0, 10}};
  Param<double> max_radius{this, "max_radius", 30.0, "m", "cap on the grown radius",
                           Range{0, 1e4}};
  Param<double> angular_window{this, "angular_window", 0.4, "rad",
                               "rotation half-width with no drift", Range{0, 3.2}};
  Param<double> angular_drift{this, "angular_drift", 0.05, "rad/m",
                              "rotation half-width grows by this per metre travelled since the "
                              "candidate",
                              Range{0, 1}};
  Param<double> max_angular_window{this, "max_angular_window", M_PI, "rad",
                                   "cap on the grown rotation half-width (a tracking failure "
                                   "can turn the path by any angle)",
                                   Range{0, M_PI}};
  Param<double> min_travel{this, "min_travel", 10.0, "m",
                           "ignore maps fewer metres back along the path", Range{0, 1e9}};
  Param<double> neighbourhood{this, "neighbourhood", 2.0, "m",
                              "the candidate's grid also holds the maps this much path before "
                              "and after it (a larger view of the place)",
                              Range{0, 1e3}};
  Param<double> max_range{this, "max_range", 20.0, "m",
                          "points farther than this from their map's origin are ignored",
                          Range{0.1, 1e4}};
  Param<double> min_score{this, "min_score", 0.6, "",
                          "mean grid score (0..1) of the query's points at the best pose",
                          Range{0, 1}};
  Param<double> min_score_margin{this, "min_score_margin", 0.03, "",
                                 "the best pose must beat any distinct pose by this much "
                                 "(rejects corridors and other ambiguous places)",
                                 Range{0, 1}};
  Param<double> unknown_score{this, "unknown_score", 0.3, "",
                              "score of a cell no ray of the candidate reached (free cells "
                              "score 0), so a query seeing more than the candidate is not "
                              "penalized as if it hit free space",
                              Range{0, 1}};
  Param<double> min_observed{this, "min_observed", 0.5, "",
                             "fraction of the query's points that must fall in cells the "
                             "candidate observed at the best pose",
                             Range{0, 1}};
  Param<int> max_candidates{this, "max_candidates", 2, "", "candidates searched per query map",
                            Range{1, 100}};
  Param<double> candidate_spacing{this, "candidate_spacing", 5.0, "m",
                                  "candidates are at least this much path apart",
                                  Range{0, 1e6}};
  Param<double> query_spacing{this, "query_spacing", 2.0, "m",
                              "search from at most one query map per this much path",
                              Range{0, 1e6}};
  Param<double> after_loop{this, "after_loop", 5.0, "m",
                           "search only when the path since the last closed loop is longer "
                           "(0: always; proximity keeps closing loops while drift is small)",
                           Range{0, 1e9}};
  Param<int> cache_size{this, "cache_size", 16, "", "candidate grids kept between searches",
                        Range{1, 10000}};

  std::vector<LoopCandidate> detect(const GraphView& view, const LocalMap& query) override;
  void configure() override;

 private:
  // The grid of candidate `id` and its neighbours older than map `before`, cached.
  std::shared_ptr<const MatchGrid> gridOf(const GraphView& view, int64_t id, int64_t before);

  struct Cached {
    int64_t id;
    std::shared_ptr<const MatchGrid> grid;
  };
  std::list<Cached> cache_;  // most recently used first
  double last_query_ = -1e300;
};

}  // namespace laser2d
}  // namespace plugslam
