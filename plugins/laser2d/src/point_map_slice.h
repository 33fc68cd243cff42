#pragma once
// laser2d.PointMapSlice: merges the measured cloud into the local map's point cloud.
#include <string>

#include "cell_index.h"
#include "plugslam/tracker_slice.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Point fusion (weighted mean of position and normal) and clipping around the robot.
class PointMapSlice final : public TrackerSlice<Space2D> {
 public:
  Input<PointCloud2D> measurement{this, Container::measurement, "measurement", "front",
                                  "measured cloud to merge (robot frame)"};
  Output<PointCloud2D> scene{this, Container::scene, "scene", "front",
                             "local map's cloud to merge into"};
  Param<double> fusion_radius{this,
                              "fusion_radius",
                              0.05,
                              "m",
                              "a measured point this close to a map point is fused into it",
                              Range{1e-4, 10}};
  Param<double> clip_radius{this,
                            "clip_radius",
                            20.0,
                            "m",
                            "map points farther than this from the robot are dropped (0: never)",
                            Range{0, 1e4}};
  Param<double> max_normal_angle{this,
                                 "max_normal_angle",
                                 0.8,
                                 "rad",
                                 "points whose normals differ more are not fused (two sides of a "
                                 "thin wall)",
                                 Range{0, M_PI}};
  Param<double> max_weight{this,
                           "max_weight",
                           20.0,
                           "",
                           "cap on a map point's observation count, so the map keeps adapting",
                           Range{1, 1e9}};

 protected:
  void integrate(const MergeContext<Space2D>& context) override;

 private:
  CellIndex index_;
};

}  // namespace laser2d
}  // namespace plugslam
