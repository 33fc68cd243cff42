#pragma once
// The two pose spaces the core modules are generic over: 2D (SE2, 3 dof) and 3D (SE3, 6 dof).
// Each names its pose type, its tangent vector and the interface kinds of its modules, so
// MultiAligner<Space2D> and MultiAligner<Space3D> are one implementation instantiated twice.
#include <Eigen/Geometry>

#include "plugslam/geometry.h"

namespace plugslam {
inline namespace abi_v1 {

/// What both spaces define alike from their dimension, degrees of freedom and pose type.
template <int Dim, int Dof, class PoseType>
struct SpaceBase {
  static constexpr int kDim = Dim;
  static constexpr int kDof = Dof;
  using Pose = PoseType;
  using Vector = Eigen::Matrix<double, Dof, 1>;
  using Matrix = Eigen::Matrix<double, Dof, Dof>;
  /// Minimal coordinates of a pose.
  static Vector toVector(const Pose& t) { return plugslam::toVector(t); }
  /// Translation norm of a relative pose.
  static double distance(const Pose& t) { return t.translation().norm(); }
};

/// Planar poses: (x, y, theta).
struct Space2D : SpaceBase<2, 3, Eigen::Isometry2d> {
  static constexpr const char* kSuffix = "2D";
  /// Right perturbation: T * exp(dx), dx = (x, y, theta).
  static Pose boxplus(const Pose& t, const Vector& dx) { return normalized(t * se2(dx)); }
  /// The same pose with an exactly orthonormal rotation. Isometry::inverse() assumes one, so
  /// products of inverses (motion deltas) would otherwise amplify rounding frame after frame.
  static Pose normalized(const Pose& t) { return se2(plugslam::toVector(t)); }
  /// Embeds the pose in 3D (rotation about z).
  static Eigen::Isometry3d to3D(const Pose& t) {
    Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
    out.linear().topLeftCorner<2, 2>() = t.linear();
    out.translation().head<2>() = t.translation();
    return out;
  }
  /// Projects a 3D pose to the plane (x, y, yaw).
  static Pose from3D(const Eigen::Isometry3d& t) {
    return se2(t.translation().x(), t.translation().y(),
               std::atan2(t.linear()(1, 0), t.linear()(0, 0)));
  }
  /// Rotation angle of a relative pose.
  static double angle(const Pose& t) {
    return std::abs(std::atan2(t.linear()(1, 0), t.linear()(0, 0)));
  }
};

/// Spatial poses: (x, y, z, rotation vector).
struct Space3D : SpaceBase<3, 6, Eigen::Isometry3d> {
  static constexpr const char* kSuffix = "3D";
  /// Right perturbation: T * exp(dx), dx = (t, rotation vector).
  static Pose boxplus(const Pose& t, const Vector& dx) { return normalized(t * se3(dx)); }
  /// The same pose with an exactly orthonormal rotation (see Space2D::normalized).
  static Pose normalized(const Pose& t) {
    Pose out = t;
    out.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
    return out;
  }
  static Eigen::Isometry3d to3D(const Pose& t) { return t; }
  static Pose from3D(const Eigen::Isometry3d& t) { return t; }
  static double angle(const Pose& t) { return Eigen::AngleAxisd(t.linear()).angle(); }
};

}  // namespace abi_v1
}  // namespace plugslam
