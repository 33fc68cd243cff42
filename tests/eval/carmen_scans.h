#pragma once
// Test-only reader of the FLASER lines of a (gzipped) CARMEN log: scans with the pose stored in
// the log. The io plugin owns the real CARMEN reader; this one only feeds the crispness check.
#include <string>
#include <vector>

#include "plugslam/eval/crispness.h"
#include "plugslam/trajectory.h"

namespace plugslam::test {

/// Scans of a log in the robot frame, beams at or beyond max_range dropped, and the log's poses.
struct CarmenScans {
  std::vector<PosedScan> scans;
  Trajectory poses;  ///< the FLASER x y theta, t = scan index (some logs carry zero stamps)
};

/// Reads every FLASER line (180/181 beams: 1 deg, 360/361: 0.5 deg, from -90 deg); throws
/// std::runtime_error on an unreadable file.
CarmenScans readCarmenScans(const std::string& path, double max_range = 80.0);

}  // namespace plugslam::test
