#pragma once
// Local-map splitter: decides when the current local map closes and a new one starts.
#include <cstddef>

#include "plugslam/configurable.h"

namespace plugslam {
inline namespace abi_v1 {

/// What the tracker knows about the current local map when it asks the splitter.
struct SplitQuery {
  double distance = 0;      ///< robot's distance from the local map's origin [m]
  double angle = 0;         ///< robot's rotation from the local map's origin [rad]
  double elapsed = 0;       ///< time since the local map started [s]
  double inlier_ratio = 1;  ///< aligner inliers / factors this frame (overlap with the map)
  size_t frames = 0;        ///< frames merged into the local map
};

/// Decides when to close the local map.
class Splitter : public Configurable {
 public:
  static constexpr const char* kKind = "Splitter";
  ~Splitter() override;
  /// True when the local map should close now.
  virtual bool split(const SplitQuery& q) const = 0;
};

/// Splits on distance, angle or time travelled, or when the overlap drops ("sdk.DistanceSplitter").
class DistanceSplitter : public Splitter {
 public:
  Param<double> distance{this, "distance", 1.0, "m", "split after this travel (0: never)",
                         Range{0, 1e6}};
  Param<double> angle{this, "angle", 0.5, "rad", "split after this rotation (0: never)",
                      Range{0, 1e3}};
  Param<double> time{this, "time", 0.0, "s", "split after this time (0: never)", Range{0, 1e9}};
  Param<double> min_inlier_ratio{this, "min_inlier_ratio", 0.0, "",
                                 "split when the aligner's inlier ratio drops below (0: never)",
                                 Range{0, 1}};
  bool split(const SplitQuery& q) const override;
};

}  // namespace abi_v1
}  // namespace plugslam
