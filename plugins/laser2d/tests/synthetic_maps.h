#pragma once
// Local maps built from synthetic scans by the cue's own preprocessor and map slice, for the
// loop detectors' tests.
#include <cstdint>
#include <memory>
#include <vector>

#include "plugslam/local_map.h"
#include "synthetic.h"

namespace plugslam::laser2d::test {

/// A local map `id` with its origin at world pose `origin`, holding the scans (1 cm range noise,
/// seeds from `seed` on) cast in `world` from the world poses `robots`, merged by a
/// PointMapSlice.
std::shared_ptr<LocalMap> mapOfScans(int64_t id, const std::vector<Segment>& world,
                                     const SE2& origin, const std::vector<SE2>& robots,
                                     uint32_t seed);

}  // namespace plugslam::laser2d::test
