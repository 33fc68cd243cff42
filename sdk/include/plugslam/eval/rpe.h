#pragma once
// Relative pose error over a fixed number of frames, distance travelled or time.
#include <string>
#include <vector>

#include "plugslam/eval/association.h"
#include "plugslam/eval/stats.h"
#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

/// The unit of the RPE step.
enum class RpeUnit {
  Frames,  ///< delta associated poses later
  Meters,  ///< first pose at least delta metres further along the reference path
  Seconds  ///< first pose at least delta seconds later on the reference clock
};

/// Name of a unit as the CLI spells it ("frames", "m", "s").
std::string toString(RpeUnit unit);
/// Parses "frames"/"f", "m"/"meters", "s"/"seconds"; throws InputError otherwise.
RpeUnit parseRpeUnit(const std::string& name);

/// Options of computeRpe.
struct RpeOptions {
  RpeUnit unit = RpeUnit::Frames;
  double delta = 1.0;     ///< step in the unit above; frames must be a positive integer
  bool all_pairs = true;  ///< every start pose; false: non-overlapping segments (evo default)
  AssociationOptions association;
};

/// One measured segment (i, j) of an RPE: where it starts and ends, and its errors.
struct RpeSegment {
  PosePair first;             ///< the associated poses at i
  PosePair last;              ///< the associated poses at j
  double translation = 0.0;   ///< |trans(E)| in metres
  double rotation_deg = 0.0;  ///< angle(E) in degrees
  double length_m = 0.0;      ///< path length along the reference from i to j
};

/// RPE: errors of E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Q reference, P estimate.
struct RpeResult {
  RpeUnit unit = RpeUnit::Frames;
  double delta = 1.0;
  std::size_t pairs = 0;    ///< number of (i, j) segments measured
  ErrorStats translation;   ///< |trans(E)| in metres
  ErrorStats rotation_deg;  ///< angle(E) in degrees
  /// 100 |trans(E)| / L_ij, L_ij the segment's path length along the reference (the drift in %
  /// of the distance travelled); segments with L_ij = 0 are left out (count says how many are in).
  ErrorStats translation_percent;
  ErrorStats length_m;  ///< L_ij in metres: how long the measured segments really are
  std::vector<RpeSegment> segments;  ///< every measured segment, in time order (for plots)
};

/// Associates by time and measures every segment; throws InputError if no segment of that
/// length exists or nothing associates.
RpeResult computeRpe(const Trajectory& reference, const Trajectory& estimate,
                     const RpeOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
