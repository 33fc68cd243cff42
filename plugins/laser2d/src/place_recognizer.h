#pragma once
// laser2d.PlaceRecognizer: loop detection that does not use the estimate, to join graph
// components (a session mapped elsewhere, a run started at an unknown pose, a tracker reset).
// The query's place (its map and the maps just before it, as the tracker placed them) is matched
// against the whole of every other component by branch and bound over all translations and a
// full turn (Hess et al., ICRA 2016, as for global localization). Maps of different components
// have no common frame, so a single match is not trusted: the graph joins two components only
// once loops from several places agree on their relative pose (GraphSlam's join_agreeing). One
// look-alike corridor must not weld two buildings together.
#include <Eigen/Geometry>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "global_match_detector.h"
#include "plugslam/entry.h"
#include "plugslam/loop_closure.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Loop detector across graph components by global scan-to-map matching
/// ("laser2d.PlaceRecognizer"); proposes nothing while the graph has one component.
class PlaceRecognizer final : public LoopDetector {
 public:
  Input<PointCloud2D> scene{this, Container::scene, "scene", "front", "local maps' cloud to match"};
  Param<double> resolution{this, "resolution", 0.1, "m",
                           "grid cell of the search (a whole component's map: coarser is faster "
                           "and less exact; the validators refine the match)",
                           Range{0.02, 1}};
  Param<double> max_range{this, "max_range", 20.0, "m",
                          "points farther than this from their map's origin are ignored (far "
                          "returns are sparse and mostly noise at this resolution)",
                          Range{0.1, 1e4}};
  Param<double> query_path{this, "query_path", 4.0, "m",
                           "the query is its map and the maps up to this much path before it: a "
                           "view of the place wide enough to be told from others",
                           Range{0, 1e3}};
  Param<double> query_voxel{this, "query_voxel", 0.25, "m",
                            "one query point per cell of this size (at least `resolution`): the "
                            "search's cost grows with the points, and a place is told by its "
                            "layout more than by its density",
                            Range{0.01, 10}};
  Param<double> query_spacing{this, "query_spacing", 2.0, "m",
                              "search from at most one query map per this much path (each search "
                              "covers whole maps); a run localizing from an unknown start is "
                              "searched whenever its view changed (sdk.Pipeline)",
                              Range{0, 1e6}};
  Param<double> min_score{this, "min_score", 0.6, "",
                          "mean grid score (0..1) of the query's points at the best pose",
                          Range{0, 1}};
  Param<double> min_score_margin{this, "min_score_margin", 0.05, "",
                                 "the best pose must beat any distinct pose by this much (a "
                                 "search over a whole building meets more look-alikes than a "
                                 "drift-sized window)",
                                 Range{0, 1}};
  Param<double> unknown_score{this, "unknown_score", 0.3, "",
                              "score of a cell no ray reached (free cells score 0)", Range{0, 1}};
  Param<double> min_observed{this, "min_observed", 0.5, "",
                             "fraction of the query's points that must fall in cells the other "
                             "component observed at the best pose",
                             Range{0, 1}};
  Param<int> max_candidates{this, "max_candidates", 3, "",
                             "maps of the other component proposed per recognized place, nearest "
                             "first (a local map holds a metre of scans and may face elsewhere)",
                             Range{1, 100}};
  std::vector<LoopCandidate> detect(const GraphView& view, const LocalMap& query) override;
  void configure() override;

 private:
  // The grid of component `component` (its maps older than `before`, placed by the estimate, in
  // the world frame), cached while the component's maps and origins stay the same.
  std::shared_ptr<const MatchGrid> gridOf(const GraphView& view, int component, int64_t before);

  struct Cached {
    int component;
    size_t maps;
    double checksum;  // sum of the maps' origin coordinates: changes when an optimization moves them
    std::shared_ptr<const MatchGrid> grid;
  };
  std::list<Cached> cache_;
  std::map<int, double> last_query_;                            // per query component
};

}  // namespace laser2d
}  // namespace plugslam
