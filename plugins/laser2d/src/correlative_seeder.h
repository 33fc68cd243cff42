#pragma once
// laser2d.CorrelativeSeeder: the front-end's recovery from a poor prediction (issue 20). When the
// ICP solve from the prediction fails, or lands farther from it than the tracker's gate, the
// scan is matched against a likelihood grid of the local map over a window around the
// prediction (branch and bound over pooled grids, the same matcher as the loop closers':
// correlative_matcher.h); the best pose, when it is unambiguous, seeds a new ICP solve.
#include <cmath>

#include "correlative_matcher.h"
#include "plugslam/align_seeder.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Seeds the Multi-Aligner with the correlative scan-to-map match around the prediction.
class CorrelativeSeeder : public AlignSeeder<Space2D> {
 public:
  Input<PointCloud2D> measurement{this, Container::measurement, "measurement", "front",
                                  "measured cloud (robot frame)"};
  Input<PointCloud2D> scene{this, Container::scene, "scene", "front",
                            "local map's cloud to search"};
  Param<double> resolution{this, "resolution", 0.05, "m",
                           "grid cell: the seed's translation step", Range{1e-3, 10}};
  Param<double> linear_window{this, "linear_window", 2.0, "m",
                              "half-width of the search in x and y around the prediction",
                              Range{0, 100}};
  Param<double> angular_window{this, "angular_window", 0.8, "rad",
                               "half-width of the search in heading around the prediction",
                               Range{0, M_PI}};
  Param<double> angular_step{this, "angular_step", 0.01, "rad",
                             "the seed's heading step (0: from the resolution and the scan's "
                             "extent)",
                             Range{0, 1}};
  Param<double> min_score{this, "min_score", 0.55, "",
                          "the best pose's mean grid value (0..1) must reach this",
                          Range{0, 1}};
  Param<double> min_score_margin{this, "min_score_margin", 0.03, "",
                                 "...and exceed any distinct pose's by this (else ambiguous)",
                                 Range{0, 1}};
  Param<double> point_extent{this, "point_extent", 0.1, "m",
                             "each map point covers this much of its wall either side",
                             Range{0, 10}};
  Param<double> max_range{this, "max_range", 30.0, "m", "scan points farther are left out",
                          Range{0.1, 1000}};
  Param<bool> with_measured_motion{
      this, "with_measured_motion", true, "",
      "also search frames whose motion the motion model measured in full (odometry read at the "
      "frame); false: only frames where it measured none (laser only: the prediction is the last "
      "step again) or extrapolated part of it (odometry read less often than the scans)"};

  void configure() override;

 protected:
  std::vector<SE2> search(const AlignContext<Space2D>& context) override;
};

}  // namespace laser2d
}  // namespace plugslam
