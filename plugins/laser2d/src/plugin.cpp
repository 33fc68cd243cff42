// The laser2d plugin's register function: every type of the cue, by name.
#include "plugslam/plugin.h"

#include "correlative_validator.h"
#include "global_match_detector.h"
#include "occupancy_map_writer.h"
#include "plugslam/view/drawers.h"
#include "point_cloud2d.h"
#include "place_recognizer.h"
#include "point_map_slice.h"
#include "scan_preprocessor.h"
#include "scan_slices.h"

PLUGSLAM_PLUGIN("laser2d", "1.0.0", "2D laser: scan preprocessing, ICP slices, point map, grid") {
  using namespace plugslam::laser2d;
  registrar.addValueType<PointCloud2D>("PointCloud2D");
  // Viewers show the cue's points: a scan in the robot's frame, a local map in its own.
  plugslam::view::Drawers::instance().add<PointCloud2D>(
      registrar.plugin(), [](const PointCloud2D& cloud, plugslam::view::PointCloud& out) {
        out.points.reserve(cloud.size());
        for (const auto& p : cloud.points)
          out.points.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
      });
  registrar.add<ScanPreprocessor>("ScanPreprocessor",
                                  "laser scan -> 2D points with normals in the robot frame");
  registrar.add<PointToLineSlice>(
      "PointToLineSlice",
      "point-to-line ICP factors (2D); scores the aligner's correlative search");
  registrar.add<PointToPointSlice>(
      "PointToPointSlice",
      "point-to-point ICP factors (2D); scores the aligner's correlative search");
  registrar.add<PointMapSlice>("PointMapSlice",
                               "merges points into the local map with fusion and clipping");
  registrar.add<OccupancyMapWriter>("OccupancyMapWriter",
                                    "occupancy grid of the run: PGM + YAML (map_server), PNG");
  registrar.add<CorrelativeValidator>(
      "CorrelativeValidator",
      "loop validator: branch-and-bound correlative scan-to-map matching over a wide window");
  registrar.add<GlobalMatchDetector>(
      "GlobalMatchDetector",
      "loop detector for large drift: branch-and-bound scan-to-map matching of the query "
      "against each nearby candidate's neighbourhood over a drift-sized window");
  registrar.add<PlaceRecognizer>(
      "PlaceRecognizer",
      "loop detector across graph components (sessions, unknown starts): the query's place "
      "matched against each whole other component, proposed once several matches agree");
}
