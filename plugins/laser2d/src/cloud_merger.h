#pragma once
// Joins the 2D point clouds of one local map's scene into another's frame, so that a loop
// validator can align against a map's whole neighbourhood at once ("laser2d.CloudMerger").
#include "plugslam/loop_closure.h"

namespace plugslam {
namespace laser2d {

/// Appends every PointCloud2D cue of a scene, moved into another scene's frame, to the cloud of
/// the same name there ("laser2d.CloudMerger").
class CloudMerger : public SceneMerger {
 public:
  Param<double> max_range{this, "max_range", 0.0, "m",
                          "points farther than this from their own map's origin are left out "
                          "(0: none)",
                          Range{0, 1e6}};
  void append(PropertyContainer& into, const PropertyContainer& from,
              const Eigen::Isometry3d& pose) override;
};

}  // namespace laser2d
}  // namespace plugslam
