#pragma once
// laser2d.ScanPreprocessor: a raw LaserScan -> a PointCloud2D in the robot frame.
#include <string>
#include <vector>

#include "plugslam/preprocessor.h"
#include "plugslam/sensor_data.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

/// Range/angle limits, normals from adjacent beams, spacing filter and the mount transform.
class ScanPreprocessor final : public PreProcessor {
 public:
  Input<LaserScan> input{this, Container::raw, "input", "front_laser", "laser scan to convert"};
  Output<PointCloud2D> output{this, Container::measurement, "output", "front",
                              "cloud with normals (robot frame)"};
  Param<double> min_range{this,
                          "min_range",
                          0.0,
                          "m",
                          "drop returns closer than this (and than the scan's range_min)",
                          Range{0, 1e4}};
  Param<double> max_range{this,
                          "max_range",
                          0.0,
                          "m",
                          "drop returns at or beyond this (0: the scan's range_max)",
                          Range{0, 1e4}};
  Param<double> min_angle{this,
                          "min_angle",
                          -M_PI,
                          "rad",
                          "first beam angle kept (sensor frame)",
                          Range{-2 * M_PI, 2 * M_PI}};
  Param<double> max_angle{this,
                          "max_angle",
                          M_PI,
                          "rad",
                          "last beam angle kept (sensor frame)",
                          Range{-2 * M_PI, 2 * M_PI}};
  Param<int> decimation{this,          "decimation", 1, "", "keep every n-th beam (after normals)",
                        Range{1, 1000}};
  Param<double> voxel{
      this,         "voxel", 0.0, "m", "minimum spacing between consecutive kept points (0: off)",
      Range{0, 100}};
  Param<int> normal_neighbors{
      this,        "normal_neighbors", 3, "", "beams on each side used to fit a point's normal",
      Range{1, 50}};
  Param<double> normal_radius{this,
                              "normal_radius",
                              0.5,
                              "m",
                              "neighbours farther than this do not enter the normal fit",
                              Range{0.001, 100}};
  // Beams 0.5 deg apart are 0.44 m apart at 50 m: a fixed radius leaves far surfaces (outdoors
  // most of the structure) without the three neighbours a normal needs, and drops them.
  Param<double> normal_spacing{this,
                               "normal_spacing",
                               2.5,
                               "",
                               "the normal fit's radius grows to this many beam spacings (range "
                               "x angle increment) where that exceeds normal_radius (0: off)",
                               Range{0, 100}};
  Param<double> max_planarity{this,
                              "max_planarity",
                              0.1,
                              "",
                              "drop a point whose fit is not line-like (lambda_min/lambda_max)",
                              Range{0, 1}};
  Param<std::vector<double>> mount{
      this,
      "mount",
      {},
      "m, m, rad",
      "sensor pose x, y, theta in the robot frame (empty: the scan's)"};

  void configure() override;
  bool process(Frame& frame) override;

  /// The conversion itself, on a scan (used by process and by tests).
  void convert(const LaserScan& scan, PointCloud2D& out);

 private:
  // Reused between frames: beam points in the sensor frame and their validity.
  std::vector<Eigen::Vector2d> beam_points_;
  std::vector<char> valid_;
};

}  // namespace laser2d
}  // namespace plugslam
