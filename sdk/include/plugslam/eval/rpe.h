#pragma once
// Relative pose error over a fixed number of frames, distance travelled or time.
#include <string>

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
};

/// Associates by time and measures every segment; throws InputError if no segment of that
/// length exists or nothing associates.
RpeResult computeRpe(const Trajectory& reference, const Trajectory& estimate,
                     const RpeOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
