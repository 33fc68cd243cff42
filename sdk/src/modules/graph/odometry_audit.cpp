#include "modules/graph/odometry_audit.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "modules/graph/global_optimizer.h"
#include "modules/graph/pose_graph.h"

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

namespace {
// Rounds of the audit: each rejects the loops of one stretch of path.
constexpr int kAuditRounds = 10;
}  // namespace

std::vector<double> OdometryAudit::strain(const std::vector<GraphEdge>& odometry,
                                          const std::vector<Eigen::Isometry3d>& estimate,
                                          int dof) const {
  std::vector<double> out;
  out.reserve(odometry.size());
  const double k = sigmas();
  for (const GraphEdge& e : odometry) {
    const Eigen::Isometry3d err = edgeError(e, estimate[e.from], estimate[e.to]);
    const auto [var_t, var_r] = maxVariances(e.information, dof);
    double s = 0;
    if (translation() > 0)
      s = err.translation().norm() / std::max(translation(), k * std::sqrt(var_t));
    if (rotation() > 0)
      s = std::max(
          s, Eigen::AngleAxisd(err.linear()).angle() / std::max(rotation(), k * std::sqrt(var_r)));
    out.push_back(s);
  }
  return out;
}

size_t OdometryAudit::runEnds(PoseGraph& graph, GraphOptimizer& optimizer) {
  std::vector<Loop>& loops = graph.loops();
  if ((translation() <= 0 && rotation() <= 0) || loops.empty()) return 0;
  // Stretches of path the front-end tied together: a tracking failure's weak edge (or a new
  // graph component) starts the next. Between stretches only the motion model's prediction
  // holds, so loops can bend the graph there; but wheel odometry between two maps does not err
  // by metres, and where the optimized graph says it did, the loops that pull a stretch there are
  // what is wrong (outdoors, a stretch tied 15 m along a repeating facade).
  const auto& maps = graph.maps();
  const auto& components = graph.components();
  const auto& weak_t = graph.weakVarianceT();
  const auto& weak_r = graph.weakVarianceR();
  const std::vector<GraphEdge>& odometry = graph.odometry();
  const auto restored = static_cast<int64_t>(graph.restoredMaps());
  const size_t n = maps.size();
  std::vector<size_t> stretch(n), length;
  size_t stretches = 0;
  for (size_t i = 0; i < n; ++i) {
    const int64_t p = maps[i]->previous;
    const bool starts =
        p < 0 || components[i] != components[p] || weak_t[i] != weak_t[p] || weak_r[i] != weak_r[p];
    stretch[i] = starts ? stretches++ : stretch[p];
    if (starts) length.push_back(0);
    ++length[stretch[i]];
  }
  // How far the odometry is bent overall: strains below the bound count too, so that a side whose
  // removal only moves the stretch to another edge (short of its bound) is not taken for a fix.
  const auto total = [](const std::vector<double>& s) {
    double t = 0;
    for (double x : s) t += x * x;
    return t;
  };
  // Edges between stretches that no side explains; edges inside a stretch are the tracker's own
  // (no loops' choice of stretch explains them) and edges between restored maps were the
  // restored session's.
  std::vector<char> settled(odometry.size(), 0);
  for (size_t j = 0; j < odometry.size(); ++j)
    settled[j] = stretch[odometry[j].from] == stretch[odometry[j].to] || odometry[j].to < restored;
  size_t rejected = 0;
  for (int round = 0; round < kAuditRounds; ++round) {
    const std::vector<double> bent = strain(odometry, optimizer.estimate(), graph.dof());
    size_t worst = odometry.size();
    for (size_t j = 0; j < bent.size(); ++j)
      if (!settled[j] && bent[j] > 1 && (worst == odometry.size() || bent[j] > bent[worst]))
        worst = j;
    if (worst == odometry.size()) break;
    // The active loops joining each stretch to another (loops among restored maps belong to
    // their own session).
    std::vector<std::vector<size_t>> joining(stretches);
    for (size_t i = 0; i < loops.size(); ++i) {
      const GraphEdge& e = loops[i].edge;
      if (!loops[i].active || stretch[e.from] == stretch[e.to]) continue;
      if (std::max(e.from, e.to) < restored) continue;
      joining[stretch[e.from]].push_back(i);
      joining[stretch[e.to]].push_back(i);
    }
    // The nearest stretch with such loops on either side of the stretched edge (stretches of
    // one failed frame each, between consecutive failures, hold none).
    const GraphEdge& edge = odometry[worst];
    std::vector<size_t> sides;
    for (int64_t m = edge.from; m >= 0; m = maps[m]->previous)
      if (!joining[stretch[m]].empty()) {
        sides.push_back(stretch[m]);
        break;
      }
    for (int64_t m = edge.to; m < static_cast<int64_t>(n);) {
      if (!joining[stretch[m]].empty()) {
        // Both sides may hold the same loops (the other side's only ones are to this one): then
        // they are tried once, named by the shorter stretch.
        if (sides.empty() || joining[sides[0]] != joining[stretch[m]])
          sides.push_back(stretch[m]);
        else if (length[stretch[m]] < length[sides[0]])
          sides[0] = stretch[m];
        break;
      }
      if (m + 1 >= static_cast<int64_t>(n) || maps[m + 1]->previous != m) break;
      ++m;
    }
    // Without one side's loops, does the edge hold, with no other edge pushed past its bound?
    // Of the sides for which it does, the one whose removal leaves the odometry least bent goes
    // (the other side's loops, right, only carry the stretch along to its next edge); on a tie,
    // the one with fewer loops.
    const double before = total(bent);
    size_t best = stretches;
    double best_total = before;
    Solution best_trial;
    for (size_t side : sides) {
      std::vector<char> drop(loops.size(), 0);
      for (size_t i : joining[side]) drop[i] = 1;
      std::vector<GraphEdge> edges = odometry;
      for (size_t i = 0; i < loops.size(); ++i)
        if (loops[i].active && !drop[i]) edges.push_back(loops[i].edge);
      Solution trial = optimizer.trial(std::move(edges));
      if (!trial.ok) continue;
      const std::vector<double> after = strain(odometry, trial.after, graph.dof());
      const double after_total = total(after);
      if (!(after[worst] <= 1) || !(after_total < before)) continue;
      bool moved = false;  // the stretch only moved to another edge
      for (size_t j = 0; j < after.size() && !moved; ++j)
        moved = j != worst && after[j] > 1 && !(bent[j] > 1);
      if (moved) continue;
      if (best == stretches || after_total < best_total ||
          (after_total == best_total && joining[side].size() <= joining[best].size())) {
        best = side;
        best_total = after_total;
        best_trial = std::move(trial);
      }
    }
    const Eigen::Isometry3d err = edgeError(edge, maps[edge.from]->origin, maps[edge.to]->origin);
    if (best == stretches) {
      spdlog::info(
          "odometry audit: the graph stretches odometry edge {} -> {} by {:.2f} m, "
          "{:.3f} rad; no side's loops explain it, kept",
          edge.from, edge.to, err.translation().norm(), Eigen::AngleAxisd(err.linear()).angle());
      settled[worst] = 1;
      continue;
    }
    for (size_t i : joining[best]) {
      loops[i].active = false;
      loops[i].vetoed = true;
      loops[i].audited = true;
    }
    // The trial is the graph without them: adopt it rather than solve it again. Those of them
    // that agree with the corrected graph (a stretch's right loops next to its wrong ones)
    // come back.
    const bool again = optimizer.adopt(best_trial);
    size_t reinstated = 0;
    const double max_t = reinstate_translation(), max_r = reinstate_rotation();
    if (max_t > 0 || max_r > 0)
      for (size_t i : joining[best]) {
        const GraphEdge& e = loops[i].edge;
        const Eigen::Isometry3d r = edgeError(e, maps[e.from]->origin, maps[e.to]->origin);
        if ((max_t > 0 && !(r.translation().norm() <= max_t)) ||
            (max_r > 0 && !(Eigen::AngleAxisd(r.linear()).angle() <= max_r)))
          continue;
        loops[i].active = true;
        loops[i].vetoed = false;
        loops[i].audited = false;
        ++reinstated;
      }
    if (again || reinstated > 0) optimizer.optimize();
    rejected += joining[best].size() - reinstated;
    int64_t first = -1, last = -1;
    for (size_t i = 0; i < n; ++i)
      if (stretch[i] == best) {
        if (first < 0) first = static_cast<int64_t>(i);
        last = static_cast<int64_t>(i);
      }
    spdlog::info(
        "odometry audit: the graph stretched odometry edge {} -> {} by {:.2f} m, "
        "{:.3f} rad; rejected {} of the {} loops joining maps {}-{} to the rest",
        edge.from, edge.to, err.translation().norm(), Eigen::AngleAxisd(err.linear()).angle(),
        joining[best].size() - reinstated, joining[best].size(), first, last);
  }
  return rejected;
}

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
