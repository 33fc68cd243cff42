#include "plugslam/solver/initialization.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <deque>
#include <unordered_map>
#include <vector>

#include "plugslam/errors.h"
#include "plugslam/solver/pose_factors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

// One relative pose measurement in matrix form, between variable indices i and j.
struct Edge {
  int i, j;
  Eigen::Matrix3d r;  // top-left d x d used in 2D
  Eigen::Vector3d t;
  double kappa, tau;
};

struct PoseGraphView {
  int dim = 0;
  std::vector<Variable*> vars;
  std::vector<Edge> edges;
};

double trace2Inverse(const Eigen::Matrix2d& m) { return m.inverse().trace(); }

PoseGraphView makeView(const FactorGraph& graph) {
  PoseGraphView view;
  std::unordered_map<const Variable*, int> index;
  for (Variable* v : graph.variables()) {
    const int d = dynamic_cast<VariableSE2*>(v) ? 2 : dynamic_cast<VariableSE3*>(v) ? 3 : 0;
    if (d == 0) continue;
    if (view.dim != 0 && view.dim != d) throw InputError("pose graph mixes SE2 and SE3 variables");
    view.dim = d;
    index.emplace(v, int(view.vars.size()));
    view.vars.push_back(v);
  }
  for (const auto& f : graph.factors()) {
    Edge e;
    if (auto* b2 = dynamic_cast<const BetweenFactorSE2*>(f.get())) {
      e.r.setIdentity();
      e.r.topLeftCorner<2, 2>() = b2->measurement().linear();
      e.t << b2->measurement().translation(), 0.0;
      const auto& inf = b2->information();
      e.tau = 2.0 / trace2Inverse(inf.topLeftCorner<2, 2>());
      e.kappa = inf(2, 2);
    } else if (auto* b3 = dynamic_cast<const BetweenFactorSE3*>(f.get())) {
      e.r = b3->measurement().linear();
      e.t = b3->measurement().translation();
      const auto& inf = b3->information();
      e.tau = 3.0 / inf.topLeftCorner<3, 3>().inverse().trace();
      e.kappa = 3.0 / (2.0 * inf.bottomRightCorner<3, 3>().inverse().trace());
    } else {
      continue;
    }
    e.i = index.at(f->variable(0));
    e.j = index.at(f->variable(1));
    // Weights only scale equations; keep them usable even for odd information matrices.
    if (!(e.tau > 0.0) || !std::isfinite(e.tau)) e.tau = 1.0;
    if (!(e.kappa > 0.0) || !std::isfinite(e.kappa)) e.kappa = 1.0;
    view.edges.push_back(e);
  }
  return view;
}

Eigen::Matrix3d rotationOf(const Variable* v, int dim) {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  if (dim == 2) {
    r.topLeftCorner<2, 2>() = static_cast<const VariableSE2*>(v)->estimate().linear();
  } else {
    r = static_cast<const VariableSE3*>(v)->estimate().linear();
  }
  return r;
}

Eigen::Vector3d translationOf(const Variable* v, int dim) {
  if (dim == 2) {
    Eigen::Vector3d t;
    t << static_cast<const VariableSE2*>(v)->estimate().translation(), 0.0;
    return t;
  }
  return static_cast<const VariableSE3*>(v)->estimate().translation();
}

void setPose(Variable* v, int dim, const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  if (dim == 2) {
    static_cast<VariableSE2*>(v)->setEstimate(se2(t.x(), t.y(), angleOf(r.topLeftCorner<2, 2>())));
  } else {
    SE3 x = SE3::Identity();
    x.linear() = r;
    x.translation() = t;
    static_cast<VariableSE3*>(v)->setEstimate(x);
  }
}

// Anchors: fixed variables, plus the first variable of each component without one.
std::vector<char> findAnchors(const PoseGraphView& g) {
  const int n = int(g.vars.size());
  std::vector<std::vector<int>> adj(n);
  for (const auto& e : g.edges) {
    adj[e.i].push_back(e.j);
    adj[e.j].push_back(e.i);
  }
  std::vector<char> anchor(n, 0);
  std::vector<int> comp(n, -1);
  int ncomp = 0;
  for (int s = 0; s < n; ++s) {
    if (comp[s] >= 0) continue;
    std::deque<int> queue{s};
    comp[s] = ncomp;
    std::vector<int> members;
    while (!queue.empty()) {
      const int u = queue.front();
      queue.pop_front();
      members.push_back(u);
      for (int w : adj[u]) {
        if (comp[w] < 0) {
          comp[w] = ncomp;
          queue.push_back(w);
        }
      }
    }
    bool has_fixed = false;
    for (int m : members) {
      if (g.vars[m]->fixed()) {
        anchor[m] = 1;
        has_fixed = true;
      }
    }
    if (!has_fixed) anchor[s] = 1;
    ++ncomp;
  }
  return anchor;
}

}  // namespace

size_t initializeSpanningTree(FactorGraph& graph) {
  const PoseGraphView g = makeView(graph);
  const int n = int(g.vars.size());
  const int d = g.dim;
  std::vector<std::vector<std::pair<int, int>>> adj(n);  // (neighbour, edge)
  for (int k = 0; k < int(g.edges.size()); ++k) {
    adj[g.edges[k].i].emplace_back(g.edges[k].j, k);
    adj[g.edges[k].j].emplace_back(g.edges[k].i, k);
  }
  const std::vector<char> anchor = findAnchors(g);
  std::vector<char> seen(n, 0);
  std::vector<Eigen::Matrix3d> r(n);
  std::vector<Eigen::Vector3d> t(n);
  std::deque<int> queue;
  for (int k = 0; k < n; ++k) {
    if (anchor[k]) {
      seen[k] = 1;
      r[k] = rotationOf(g.vars[k], d);
      t[k] = translationOf(g.vars[k], d);
      queue.push_back(k);
    }
  }
  size_t set = 0;
  // Edges are visited in file order per vertex, so the tree follows odometry first.
  while (!queue.empty()) {
    const int u = queue.front();
    queue.pop_front();
    for (auto [w, k] : adj[u]) {
      if (seen[w]) continue;
      const Edge& e = g.edges[k];
      if (e.i == u) {
        r[w] = r[u] * e.r;
        t[w] = t[u] + r[u] * e.t;
      } else {
        r[w] = r[u] * e.r.transpose();
        t[w] = t[u] - r[w] * e.t;
      }
      seen[w] = 1;
      setPose(g.vars[w], d, r[w], t[w]);
      ++set;
      queue.push_back(w);
    }
  }
  return set;
}

void initializeChordal(FactorGraph& graph) {
  const PoseGraphView g = makeView(graph);
  const int n = int(g.vars.size());
  const int d = g.dim;
  if (n == 0) return;
  const std::vector<char> anchor = findAnchors(g);
  std::vector<int> col(n, -1);
  int nfree = 0;
  for (int k = 0; k < n; ++k) {
    if (!anchor[k]) col[k] = nfree++;
  }
  std::vector<Eigen::Matrix3d> r(n);
  std::vector<Eigen::Vector3d> t(n);
  for (int k = 0; k < n; ++k) {
    r[k] = rotationOf(g.vars[k], d);
    t[k] = translationOf(g.vars[k], d);
  }
  if (nfree == 0) return;

  // Rotations. Unknown per pose: one row of R (as a d-vector x); the d rows are independent
  // problems sharing one matrix. Residual x_j - Rij^T x_i, weight kappa.
  {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nfree * d, d);
    trip.reserve(g.edges.size() * (2 * d + 2 * d * d));
    for (const auto& e : g.edges) {
      const Eigen::Matrix3d a = e.r.transpose();  // x_j = A x_i (top-left d x d in 2D)
      const double w = e.kappa;
      const int ci = col[e.i], cj = col[e.j];
      for (int p = 0; p < d; ++p) {
        if (ci >= 0) trip.emplace_back(ci * d + p, ci * d + p, w);  // A^T A = I
        if (cj >= 0) trip.emplace_back(cj * d + p, cj * d + p, w);
      }
      if (ci >= 0 && cj >= 0) {
        for (int p = 0; p < d; ++p) {
          for (int q = 0; q < d; ++q) {
            trip.emplace_back(ci * d + p, cj * d + q, -w * a(q, p));  // -A^T
            trip.emplace_back(cj * d + p, ci * d + q, -w * a(p, q));  // -A
          }
        }
      } else if (cj >= 0) {
        // x_i known (row k of R_i): H_jj x_j = w A x_i.
        const Eigen::Matrix3d m = w * a * r[e.i].transpose();  // column k = w A (row k of R_i)^T
        for (int k = 0; k < d; ++k)
          for (int p = 0; p < d; ++p) rhs(cj * d + p, k) += m(p, k);
      } else if (ci >= 0) {
        const Eigen::Matrix3d m = w * a.transpose() * r[e.j].transpose();
        for (int k = 0; k < d; ++k)
          for (int p = 0; p < d; ++p) rhs(ci * d + p, k) += m(p, k);
      }
    }
    Eigen::SparseMatrix<double> h(nfree * d, nfree * d);
    h.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(h);
    if (solver.info() != Eigen::Success)
      throw Error("chordal initialisation: rotation system is singular");
    const Eigen::MatrixXd x = solver.solve(rhs);
    for (int k = 0; k < n; ++k) {
      if (col[k] < 0) continue;
      Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
      for (int row = 0; row < d; ++row) {
        m.block(row, 0, 1, d) = x.block(col[k] * d, row, d, 1).transpose();
      }
      if (d == 2) {
        r[k].setIdentity();
        r[k].topLeftCorner<2, 2>() = projectToSO2(m.topLeftCorner<2, 2>());
      } else {
        r[k] = projectToSO3(m);
      }
    }
  }

  // Translations: residual t_j - t_i - R_i t_ij, weight tau; a weighted Laplacian per axis.
  {
    std::vector<Eigen::Triplet<double>> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nfree, d);
    trip.reserve(g.edges.size() * 4);
    for (const auto& e : g.edges) {
      const double w = e.tau;
      const Eigen::Vector3d m = r[e.i] * e.t;
      const int ci = col[e.i], cj = col[e.j];
      if (ci >= 0) {
        trip.emplace_back(ci, ci, w);
        for (int p = 0; p < d; ++p) rhs(ci, p) -= w * m[p];
      }
      if (cj >= 0) {
        trip.emplace_back(cj, cj, w);
        for (int p = 0; p < d; ++p) rhs(cj, p) += w * m[p];
      }
      if (ci >= 0 && cj >= 0) {
        trip.emplace_back(ci, cj, -w);
        trip.emplace_back(cj, ci, -w);
      } else if (cj >= 0) {
        for (int p = 0; p < d; ++p) rhs(cj, p) += w * t[e.i][p];
      } else if (ci >= 0) {
        for (int p = 0; p < d; ++p) rhs(ci, p) += w * t[e.j][p];
      }
    }
    Eigen::SparseMatrix<double> h(nfree, nfree);
    h.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(h);
    if (solver.info() != Eigen::Success)
      throw Error("chordal initialisation: translation system is singular");
    const Eigen::MatrixXd x = solver.solve(rhs);
    for (int k = 0; k < n; ++k) {
      if (col[k] < 0) continue;
      t[k].setZero();
      t[k].head(d) = x.row(col[k]).transpose();
    }
  }
  for (int k = 0; k < n; ++k) {
    if (col[k] >= 0) setPose(g.vars[k], d, r[k], t[k]);
  }
}

std::vector<Eigen::Vector2d> seSyncWeights(const FactorGraph& graph) {
  const PoseGraphView g = makeView(graph);
  std::vector<Eigen::Vector2d> w;
  w.reserve(g.edges.size());
  for (const auto& e : g.edges) w.emplace_back(e.kappa, e.tau);
  return w;
}

double seSyncObjective(const FactorGraph& graph, const std::vector<Eigen::Vector2d>& weights) {
  const PoseGraphView g = makeView(graph);
  if (weights.size() != g.edges.size()) {
    throw InputError("seSyncObjective: " + std::to_string(weights.size()) + " weights for " +
                     std::to_string(g.edges.size()) + " between factors");
  }
  double f = 0.0;
  for (size_t k = 0; k < g.edges.size(); ++k) {
    const Edge& e = g.edges[k];
    const Eigen::Matrix3d ri = rotationOf(g.vars[e.i], g.dim);
    const Eigen::Matrix3d rj = rotationOf(g.vars[e.j], g.dim);
    const Eigen::Vector3d ti = translationOf(g.vars[e.i], g.dim);
    const Eigen::Vector3d tj = translationOf(g.vars[e.j], g.dim);
    f += weights[k][0] * (rj - ri * e.r).squaredNorm() +
         weights[k][1] * (tj - ti - ri * e.t).squaredNorm();
  }
  return f;
}

double seSyncObjective(const FactorGraph& graph) {
  return seSyncObjective(graph, seSyncWeights(graph));
}

size_t applySeSyncWeights(FactorGraph& graph) {
  size_t changed = 0;
  for (const auto& f : graph.factors()) {
    if (auto* e3 = dynamic_cast<BetweenFactorSE3*>(f.get())) {
      const auto& inf = e3->information();
      const double tau = 3.0 / inf.topLeftCorner<3, 3>().inverse().trace();
      const double kappa = 3.0 / (2.0 * inf.bottomRightCorner<3, 3>().inverse().trace());
      // |Rj - Ri Rij|_F^2 = 8 |q.vec|^2 for the error rotation.
      Eigen::Matrix<double, 6, 1> d;
      d << tau, tau, tau, 8.0 * kappa, 8.0 * kappa, 8.0 * kappa;
      e3->setInformation(d.asDiagonal());
      ++changed;
    } else if (auto* e2 = dynamic_cast<BetweenFactorSE2*>(f.get())) {
      const auto& inf = e2->information();
      const double tau = 2.0 / inf.topLeftCorner<2, 2>().inverse().trace();
      e2->setInformation(Eigen::Vector3d(tau, tau, 2.0 * inf(2, 2)).asDiagonal());
      ++changed;
    }
  }
  return changed;
}

}  // namespace abi_v1
}  // namespace plugslam
