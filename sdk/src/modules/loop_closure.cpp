#include "plugslam/loop_closure.h"

#include <algorithm>

#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

std::vector<LoopCandidate> ProximityDetector::detect(const GraphView& view,
                                                     const LocalMap& query) {
  std::vector<std::pair<double, int64_t>> found;
  const Eigen::Vector3d at = view.origins.at(query.id).translation();
  const double here = view.travelled.at(query.id);
  for (const auto& map : view.maps) {
    if (map->id >= query.id) continue;
    const double since = here - view.travelled[map->id];
    if (since < min_travel()) continue;
    const double gate = std::min(max_radius(), radius() + drift() * since);
    const double d = (view.origins[map->id].translation() - at).norm();
    if (d <= gate) found.emplace_back(d, map->id);
  }
  std::sort(found.begin(), found.end());
  std::vector<LoopCandidate> out;
  for (size_t i = 0; i < found.size() && static_cast<int>(out.size()) < max_candidates(); ++i) {
    const int64_t id = found[i].second;
    const bool crowded = std::any_of(out.begin(), out.end(), [&](const LoopCandidate& c) {
      return std::abs(view.travelled[c.id] - view.travelled[id]) < spacing();
    });
    if (crowded) continue;
    LoopCandidate c;
    c.id = id;
    c.score = found[i].first;
    out.push_back(c);
  }
  return out;
}

SceneMerger::~SceneMerger() = default;

std::vector<int64_t> pathNeighbours(const GraphView& view, int64_t id, double length,
                                    int64_t before, double min_gap) {
  std::vector<std::pair<double, int64_t>> found;
  const auto n = static_cast<int64_t>(view.maps.size());
  if (id < 0 || id >= n || length <= 0) return {};
  before = std::min(before, n);
  const double end = before < n ? view.travelled[before] : view.travelled[n - 1];
  const double at = view.travelled[id];
  // A neighbour must be joined to `id` by odometry edges only: walking stops where a chain
  // starts anew (a tracker reset or another session), whose relative placement is unknown.
  const auto usable = [&](int64_t k) { return k < before && end - view.travelled[k] >= min_gap; };
  for (int64_t k = id; k > 0 && view.maps[k]->previous == k - 1; --k) {
    const double d = at - view.travelled[k - 1];
    if (d > length) break;
    if (usable(k - 1)) found.emplace_back(d, k - 1);
  }
  for (int64_t k = id + 1; k < before && view.maps[k]->previous == k - 1; ++k) {
    const double d = view.travelled[k] - at;
    if (d > length || !usable(k)) break;
    found.emplace_back(d, k);
  }
  std::sort(found.begin(), found.end());
  std::vector<int64_t> out;
  out.reserve(found.size());
  for (const auto& f : found) out.push_back(f.second);
  return out;
}

template <class S>
AlignmentValidator<S>::AlignmentValidator() = default;
template <class S>
AlignmentValidator<S>::~AlignmentValidator() = default;

template <class S>
bool AlignmentValidator<S>::validate(const LocalMap& candidate, const LocalMap& query,
                                     const Eigen::Isometry3d& guess, LoopClosure& closure,
                                     std::string& reason) {
  if (neighbourhood() > 0 || query_neighbourhood() > 0) {
    reason = "a neighbourhood needs the graph (validateInView)";
    return false;
  }
  return check(candidate.scene, query.scene, guess, closure, reason);
}

template <class S>
PropertyContainer AlignmentValidator<S>::widened(const GraphView& view, const LocalMap& map,
                                                 double length, int64_t before, double min_gap) {
  PropertyContainer scene = map.scene;
  for (int64_t k : pathNeighbours(view, map.id, length, before, min_gap))
    merger->append(scene, view.maps[k]->scene, view.relative(map.id, k));
  return scene;
}

template <class S>
bool AlignmentValidator<S>::validateInView(const GraphView& view, const LocalMap& candidate,
                                           const LocalMap& query, const Eigen::Isometry3d& guess,
                                           LoopClosure& closure, std::string& reason) {
  const double around = neighbourhood(), behind = query_neighbourhood();
  if (around <= 0 && behind <= 0) return check(candidate.scene, query.scene, guess, closure, reason);
  if (!merger) throw InputError("AlignmentValidator: a neighbourhood needs a `merger`");
  // The candidate's neighbourhood keeps clear of the query's own recent path (which would
  // otherwise vouch for the query).
  const PropertyContainer wide_candidate =
      around > 0 ? widened(view, candidate, around, query.id, around + behind) : candidate.scene;
  const PropertyContainer wide_query =
      behind > 0 ? widened(view, query, behind, query.id, 0) : query.scene;
  return check(wide_candidate, wide_query, guess, closure, reason);
}

template <class S>
bool AlignmentValidator<S>::check(const PropertyContainer& candidate,
                                  const PropertyContainer& query, const Eigen::Isometry3d& guess,
                                  LoopClosure& closure, std::string& reason) {
  if (!aligner || aligner->slices.empty()) {
    reason = "the validator's aligner has no slices";
    return false;
  }
  // The query's scene plays the measurement: its cues have the names the slices bind to.
  Frame frame;
  frame.measurement = query;
  const typename S::Pose g = S::from3D(guess);
  AlignResult<S> r = aligner->align(frame, candidate, AlignContext<S>{g, g});
  if (!r.valid) {
    reason = "alignment failed (" + std::to_string(r.inliers) + " inliers; " +
             describeCues(r.cues) + ")";
    return false;
  }
  // Two different fractions: of the pairs the association made (a wrong pose pairs points too,
  // but few within the inlier band), and of all the query's elements (how much of the query the
  // candidate explains; known from the cues that count their candidates).
  const double ratio = r.inlierRatio();
  if (ratio < min_inlier_ratio()) {
    reason = "inlier ratio " + std::to_string(ratio) + " below " +
             std::to_string(min_inlier_ratio()) + " (" + describeCues(r.cues) + ")";
    return false;
  }
  const bool counted = r.candidates > 0;
  const double overlap = counted ? r.overlap() : ratio;
  if (counted && overlap < min_overlap()) {
    reason = "overlap " + std::to_string(overlap) + " below " + std::to_string(min_overlap()) +
             " (" + describeCues(r.cues) + ")";
    return false;
  }
  const double residual = r.inliers ? r.chi2 / r.inliers : 0;
  if (residual > max_residual()) {
    reason = "residual " + std::to_string(residual) + " above " + std::to_string(max_residual());
    return false;
  }
  const double correction = (S::to3D(r.pose).translation() - guess.translation()).norm();
  if (correction > max_correction()) {
    reason = "correction " + std::to_string(correction) + " m above " +
             std::to_string(max_correction());
    return false;
  }
  closure.edge.relative = S::to3D(r.pose);
  closure.edge.information = r.H;
  closure.overlap = overlap;
  closure.residual = residual;
  return true;
}

template class AlignmentValidator<Space2D>;
template class AlignmentValidator<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
