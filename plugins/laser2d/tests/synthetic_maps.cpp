#include "synthetic_maps.h"

#include "plugslam/frame.h"
#include "plugslam/pose_space.h"
#include "point_map_slice.h"
#include "scan_preprocessor.h"

namespace plugslam::laser2d::test {

std::shared_ptr<LocalMap> mapOfScans(int64_t id, const std::vector<Segment>& world,
                                     const SE2& origin, const std::vector<SE2>& robots,
                                     uint32_t seed) {
  ScanPreprocessor pre;
  pre.configure();
  PointMapSlice slice;
  slice.configure();
  auto map = std::make_shared<LocalMap>();
  map->id = id;
  map->origin = Space2D::to3D(origin);
  for (const SE2& robot : robots) {
    ScanSpec spec;
    spec.noise = 0.01;
    spec.seed = seed++;
    Frame frame;
    frame.raw.set("front_laser", castScan(world, robot, spec));
    pre.process(frame);
    slice.merge(frame, map->scene, origin.inverse() * robot);
  }
  return map;
}

}  // namespace plugslam::laser2d::test
