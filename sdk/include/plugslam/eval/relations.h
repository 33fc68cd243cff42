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
  /// A relation timestamp matches the estimate pose nearest in time within this (s).
  double max_time_diff = 0.01;
};

/// Relation errors. For each relation, E = (P1^-1 P2) delta^-1 (as Cartographer's
/// compute_relations_metrics); mean ± sample std of |trans(E)|, |trans(E)|^2, angle(E) and
/// angle(E)^2. Rotation is in degrees.
struct RelationResult {
  std::size_t relations = 0;  ///< relations given
  std::size_t used = 0;       ///< relations whose two timestamps matched estimate poses
  MeanStd translation;        ///< m
  MeanStd translation_sq;     ///< m^2
  MeanStd rotation_deg;       ///< deg
  MeanStd rotation_sq_deg;    ///< deg^2
};

/// Scores an estimate against relations; relations whose timestamps have no estimate pose are
/// skipped (counted in relations - used). Throws InputError when none can be used.
RelationResult evaluateRelations(const Trajectory& estimate, const std::vector<Relation>& relations,
                                 const RelationOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
