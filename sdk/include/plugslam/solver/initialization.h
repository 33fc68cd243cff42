#pragma once
// Initial estimates for pose graphs built from SE2/SE3 between factors, and the SE-Sync
// objective used to compare estimates across solvers.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "plugslam/solver/factor_graph.h"

namespace plugslam {
inline namespace abi_v1 {

/// Composes between-factor measurements along a breadth-first spanning tree from the anchors
/// (fixed variables, else the first variable of each connected component, kept where they are).
/// Returns the number of variables whose estimate was set.
size_t initializeSpanningTree(FactorGraph& graph);

/// Chordal initialisation: rotations by linear least squares on the rotation-matrix entries
/// (weights kappa) projected to SO(n), then translations by linear least squares (weights tau)
/// given those rotations. Anchors as in initializeSpanningTree.
void initializeChordal(FactorGraph& graph);

/// SE-Sync objective sum kappa |Rj - Ri Rij|_F^2 + tau |tj - ti - Ri tij|^2 over the SE2/SE3
/// between factors, with 2D: tau = 2 / tr(It^-1), kappa = I_thth; 3D: tau = 3 / tr(It^-1),
/// kappa = 3 / (2 tr(IR^-1)).
double seSyncObjective(const FactorGraph& graph);

/// The SE-Sync weights (kappa, tau) of each SE2/SE3 between factor, in factor order.
std::vector<Eigen::Vector2d> seSyncWeights(const FactorGraph& graph);

/// The SE-Sync objective with given weights (from seSyncWeights, e.g. taken before
/// applySeSyncWeights changed the information matrices).
double seSyncObjective(const FactorGraph& graph, const std::vector<Eigen::Vector2d>& weights);

/// Replaces each SE2/SE3 between factor's information by SE-Sync's isotropic weights, so that
/// chi2 equals the SE-Sync objective (3D: exactly, diag(tau I, 8 kappa I) on (t, q.vec); 2D: to
/// second order in the angle error, diag(tau, tau, 2 kappa)). Returns the factors changed.
size_t applySeSyncWeights(FactorGraph& graph);

}  // namespace abi_v1
}  // namespace plugslam
