#pragma once
// The relation metric of Kümmerle et al. 2009, "On measuring the accuracy of SLAM algorithms".
#include <string>
#include <vector>

#include "plugslam/eval/stats.h"
#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

/// The expected motion from the pose at t1 to the pose at t2, in the frame of the pose at t1.
struct Relation {
  double t1 = 0.0;
  double t2 = 0.0;
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
};

/// Reads a .relations file as published with Kümmerle et al.: one relation per line,
/// `t1 t2 x y z roll pitch yaw` (angles in radians, R = Rz(yaw) Ry(pitch) Rx(roll)); '#'
/// comments. Throws ParseError on malformed lines and on an empty file.
std::vector<Relation> readRelations(const std::string& path);

/// Writes relations in the same format, atomically.
void writeRelations(const std::vector<Relation>& relations, const std::string& path);

/// Relations measured on a reference trajectory: every consecutive pair, plus every pair whose
/// positions are at most max_distance metres apart (loop-closing pairs). max_distance <= 0 gives
/// consecutive pairs only.
std::vector<Relation> relationsFromTrajectory(const Trajectory& reference, double max_distance);

/// Options of evaluateRelations.
struct RelationOptions {
  /// A relation's t1 and t2 each match the estimate pose nearest in time, if within this (s).
  /// The default is 1 us: a relation names its scans by their exact stamps, which a trajectory
  /// printed to the microsecond still carries, and scans are never that close, so it cannot
  /// match a neighbouring scan's pose.
  double max_time_diff = 1e-6;
};

/// Relation errors as the benchmark of Kümmerle et al. 2009 defines them: for each relation the
/// error motion E = delta^-1 * (P(t1)^-1 * P(t2)) (the estimate's motion "ominus" the relation,
/// P the estimate poses); mean and sample std of |trans(E)|, |trans(E)|^2, angle(E) and
/// angle(E)^2. Rotation is in degrees.
struct RelationResult {
  std::size_t relations = 0;     ///< relations given
  std::size_t used = 0;          ///< relations whose two timestamps matched estimate poses
  std::size_t missing_t1 = 0;    ///< not used: no estimate pose at t1 (t2 had one)
  std::size_t missing_t2 = 0;    ///< not used: no estimate pose at t2 (t1 had one)
  std::size_t missing_both = 0;  ///< not used: no estimate pose at t1 nor at t2
  double max_time_diff = 0.0;    ///< the matching tolerance used (s)
  double largest_dt = 0.0;       ///< largest |relation stamp - matched estimate stamp| (s)
  MeanStd translation;           ///< m
  MeanStd translation_sq;        ///< m^2
  MeanStd rotation_deg;          ///< deg
  MeanStd rotation_sq_deg;       ///< deg^2
};

/// The error motion of one relation (Kümmerle et al. 2009): delta^-1 * (p1^-1 * p2), where p1
/// and p2 are the estimate's poses at the relation's t1 and t2.
Eigen::Isometry3d relationError(const Relation& relation, const Eigen::Isometry3d& p1,
                                const Eigen::Isometry3d& p2);

/// Scores an estimate against relations; relations with a timestamp that has no estimate pose
/// within options.max_time_diff are skipped and counted by which stamp failed. Throws
/// InputError when none can be used, saying why.
RelationResult evaluateRelations(const Trajectory& estimate, const std::vector<Relation>& relations,
                                 const RelationOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
