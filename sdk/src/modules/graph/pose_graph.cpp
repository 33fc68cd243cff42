#include "modules/graph/pose_graph.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

namespace {
// Path length put between graph components (sessions, tracker resets): their maps are never
// "recently travelled" from each other, and detectors use their widest search gate.
constexpr double kComponentGap = 1e6;
}  // namespace

Eigen::MatrixXd conditionedInformation(const Eigen::MatrixXd& h, int dof) {
  if (h.rows() != dof || h.cols() != dof || !h.allFinite())
    return Eigen::MatrixXd::Identity(dof, dof);
  Eigen::MatrixXd sym = 0.5 * (h + h.transpose());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(sym);
  Eigen::VectorXd ev = eig.eigenvalues();
  double floor = std::max(1e-6, 1e-6 * ev.maxCoeff());
  for (int i = 0; i < ev.size(); ++i) ev[i] = std::max(ev[i], floor);
  return eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
}

std::pair<double, double> maxVariances(const Eigen::MatrixXd& information, int dof) {
  const Eigen::MatrixXd cov = information.rows() == dof && information.cols() == dof
                                  ? Eigen::MatrixXd(information.inverse())
                                  : Eigen::MatrixXd::Identity(dof, dof);
  const int first_rotation = dof == 3 ? 2 : 3;  // (x, y, theta) or (x, y, z, rotation)
  double var_t = 0, var_r = 0;
  for (int i = 0; i < first_rotation; ++i) var_t = std::max(var_t, cov(i, i));
  for (int i = first_rotation; i < dof; ++i) var_r = std::max(var_r, cov(i, i));
  return {var_t, var_r};
}

Eigen::Isometry3d edgeError(const GraphEdge& e, const Eigen::Isometry3d& from,
                            const Eigen::Isometry3d& to) {
  return e.relative.inverse() * from.inverse() * to;
}

PoseGraph::PoseGraph(int dimension, double weak_edge_ratio)
    : dimension_(dimension), weak_edge_ratio_(weak_edge_ratio) {}

void PoseGraph::addMap(const std::shared_ptr<LocalMap>& map, double information_scale) {
  if (map->id != static_cast<int64_t>(maps_.size()))
    throw Error("graph back-end: local map " + std::to_string(map->id) + " arrived out of order");
  double travelled = maps_.empty() ? 0.0 : travelled_.back() + kComponentGap;
  const GraphEdge* odometry = nullptr;
  if (map->previous >= 0) {
    if (map->previous >= static_cast<int64_t>(maps_.size()))
      throw Error("graph back-end: local map " + std::to_string(map->id) +
                  " follows an unknown map " + std::to_string(map->previous));
    travelled = travelled_[map->previous] + map->relative.translation().norm();
    GraphEdge e;
    e.from = map->previous;
    e.to = map->id;
    e.relative = map->relative;
    e.information = information_scale * conditionedInformation(map->information, dof());
    odometry_.push_back(std::move(e));
    odometry = &odometry_.back();
  }
  addChain(map->previous, odometry);
  maps_.push_back(map);
  travelled_.push_back(travelled);
}

void PoseGraph::restore(const std::vector<std::shared_ptr<LocalMap>>& maps,
                        const std::vector<GraphEdge>& edges) {
  if (!maps_.empty()) throw InputError("a graph can only be restored into an empty back-end");
  const int dof = this->dof();
  for (const auto& m : maps) {
    if (m->dimension != dimension_)
      throw InputError("saved local map " + std::to_string(m->id) + " is " +
                       std::to_string(m->dimension) + "D; this back-end is " +
                       std::to_string(dimension_) + "D");
    if (m->id != static_cast<int64_t>(maps_.size()) || m->previous >= m->id)
      throw InputError("saved local maps must have ids 0, 1, 2, ... in order");
    // The same travelled distance addMap computed when the map was first added.
    double travelled = maps_.empty() ? 0.0 : travelled_.back() + kComponentGap;
    if (m->previous >= 0) travelled = travelled_[m->previous] + m->relative.translation().norm();
    maps_.push_back(m);
    travelled_.push_back(travelled);
  }
  for (const auto& e : edges) {
    if (e.from < 0 || e.to < 0 || e.from >= static_cast<int64_t>(maps_.size()) ||
        e.to >= static_cast<int64_t>(maps_.size()))
      throw InputError("saved edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                       " names a map that is not in the session");
    if (e.information.rows() != dof || e.information.cols() != dof)
      throw InputError("saved edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                       " has a " + std::to_string(e.information.rows()) + "x" +
                       std::to_string(e.information.cols()) + " information matrix, expected " +
                       std::to_string(dof) + "x" + std::to_string(dof));
    // Information was conditioned and scaled when the edge was first added: kept as saved.
    if (e.loop)
      loops_.push_back(Loop{e, true});
    else
      odometry_.push_back(e);
  }
  // The chain's components and weak edges, as addMap found them when the maps were added.
  for (size_t i = 0; i < maps_.size(); ++i) {
    const int64_t prev = maps_[i]->previous;
    const GraphEdge* odometry = nullptr;
    for (const auto& e : odometry_)
      if (e.to == static_cast<int64_t>(i) && e.from == prev) odometry = &e;
    addChain(prev, odometry);
  }
  restored_maps_ = maps_.size();
  restored_loops_ = loops_.size();
}

void PoseGraph::addChain(int64_t previous, const GraphEdge* odometry) {
  if (previous < 0 || !odometry) {
    components_.push_back(components_.empty() ? 0 : components_.back() + 1);
    weak_var_t_.push_back(0);
    weak_var_r_.push_back(0);
    return;
  }
  double var_t = 0, var_r = 0;
  if (isWeak(*odometry)) std::tie(var_t, var_r) = maxVariances(odometry->information, dof());
  components_.push_back(components_[previous]);
  weak_var_t_.push_back(weak_var_t_[previous] + var_t);
  weak_var_r_.push_back(weak_var_r_[previous] + var_r);
}

bool PoseGraph::isWeak(const GraphEdge& e) {
  constexpr size_t kRecent = 200, kMinRecent = 10;
  const int dof = this->dof();
  if (e.information.rows() != dof) return true;
  const Eigen::MatrixXd cov = e.information.inverse();
  double var = 0;
  const int first_rotation = dof == 3 ? 2 : 3;  // (x, y, theta) or (x, y, z, rotation)
  for (int i = first_rotation; i < dof; ++i) var = std::max(var, cov(i, i));
  const double sigma = std::sqrt(var);
  bool loose = false;
  if (recent_sigmas_.size() >= kMinRecent) {
    std::vector<double> sorted = recent_sigmas_;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    loose = sigma > weak_edge_ratio_ * sorted[sorted.size() / 2];
  }
  // A weak edge is not remembered: the median stays the median of the tracker's good edges.
  if (!loose) {
    if (recent_sigmas_.size() < kRecent) {
      recent_sigmas_.push_back(sigma);
    } else {
      recent_sigmas_[next_sigma_] = sigma;
      next_sigma_ = (next_sigma_ + 1) % kRecent;
    }
  }
  return loose;
}

std::vector<GraphEdge> PoseGraph::edges() const {
  std::vector<GraphEdge> out = odometry_;
  for (const auto& l : loops_)
    if (l.active) out.push_back(l.edge);
  return out;
}

GraphView PoseGraph::view() const {
  GraphView view;
  view.maps.assign(maps_.begin(), maps_.end());
  view.origins.reserve(maps_.size());
  for (const auto& m : maps_) view.origins.push_back(m->origin);
  view.travelled = travelled_;
  for (const auto& l : loops_)
    if (l.active)
      view.last_loop_travelled = std::max(view.last_loop_travelled, travelled_[l.edge.to]);
  // What joins maps, without the information matrices (views are taken at every map closing).
  std::vector<GraphEdge> joins;
  joins.reserve(odometry_.size() + loops_.size());
  const auto join = [&joins](const GraphEdge& e) {
    GraphEdge j;
    j.from = e.from;
    j.to = e.to;
    joins.push_back(j);
  };
  for (const auto& e : odometry_) join(e);
  for (const auto& l : loops_)
    if (l.active) join(l.edge);
  view.components.reserve(maps_.size());
  for (int64_t c : graphComponents(maps_.size(), joins))
    view.components.push_back(static_cast<int>(c));
  return view;
}

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
