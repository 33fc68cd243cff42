#pragma once
// Absolute trajectory error after an optional rigid or similarity alignment.
#include <string>
#include <vector>

#include "plugslam/eval/association.h"
#include "plugslam/eval/stats.h"
#include "plugslam/trajectory.h"

namespace plugslam {
inline namespace abi_v1 {

/// How the estimate is aligned to the reference before measuring errors.
enum class Alignment {
  None,  ///< compare as given
  SE2,   ///< yaw about z and x, y translation (planar robots)
  SE3,   ///< rotation and translation (Umeyama without scale)
  Sim3   ///< rotation, translation and scale (Umeyama), for monocular estimates
};

/// Name of an alignment as the CLI spells it ("none", "se2", "se3", "sim3").
std::string toString(Alignment alignment);
/// Parses "none", "se2", "se3" or "sim3" (any case); throws InputError otherwise.
Alignment parseAlignment(const std::string& name);

/// The similarity x -> scale * rotation * x + translation that maps estimate onto reference.
struct SimilarityTransform {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;
};

/// Least-squares alignment of est onto ref (paired columns); SE2 solves yaw and x, y only.
/// Throws InputError with fewer than 3 points (2 for SE2) or if they are all identical.
SimilarityTransform alignPoints(const std::vector<Eigen::Vector3d>& ref,
                                const std::vector<Eigen::Vector3d>& est, Alignment alignment);

/// Options of computeAte.
struct AteOptions {
  Alignment alignment = Alignment::SE3;
  AssociationOptions association;
};

/// ATE: per associated pose, the position error (m) and rotation error (deg) after alignment.
struct AteResult {
  Alignment alignment = Alignment::SE3;
  SimilarityTransform transform;  ///< applied to the estimate
  std::size_t reference_poses = 0;
  std::size_t estimate_poses = 0;
  ErrorStats translation;                  ///< |p_ref - (s R p_est + t)| in metres
  ErrorStats rotation_deg;                 ///< angle of R_ref^T R R_est in degrees
  std::vector<double> translation_errors;  ///< one per associated pair, in time order
  std::vector<PosePair> pairs;             ///< the associated poses, same order as the errors
};

/// Associates the trajectories by time, aligns and measures; throws InputError if nothing
/// associates or too few pairs for the alignment.
AteResult computeAte(const Trajectory& reference, const Trajectory& estimate,
                     const AteOptions& options = {});

}  // namespace abi_v1
}  // namespace plugslam
