#include "plugslam/correlative_search.h"

#include <algorithm>
#include <cmath>

#include "plugslam/geometry.h"

namespace plugslam {
inline namespace abi_v1 {

LatticeScorer::~LatticeScorer() = default;

template <class S>
typename S::Pose SearchLattice<S>::pose(int a, int x, int y) const {
  // Turned about the scene's vertical axis through the center, moved in the scene's plane: the
  // lattice's cells are the scene's, so a scorer rasterizes the scene once for every heading.
  Eigen::Isometry3d c = S::to3D(center);
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() =
      Eigen::AngleAxisd(a * angular_step, Eigen::Vector3d::UnitZ()).toRotationMatrix() * c.linear();
  p.translation() = c.translation() + Eigen::Vector3d(x * resolution, y * resolution, 0);
  return S::normalized(S::from3D(p));
}

template <class S>
bool SearchLattice<S>::nearest(const typename S::Pose& p, int& a, int& x, int& y) const {
  const Eigen::Isometry3d c = S::to3D(center), q = S::to3D(p);
  const Eigen::Matrix3d turn = q.linear() * c.linear().transpose();
  const double yaw = std::atan2(turn(1, 0), turn(0, 0));
  const Eigen::Vector3d d = q.translation() - c.translation();
  a = angular_step > 0 ? static_cast<int>(std::lround(yaw / angular_step)) : 0;
  x = static_cast<int>(std::lround(d.x() / resolution));
  y = static_cast<int>(std::lround(d.y() / resolution));
  return std::abs(a) <= angles && std::abs(x) <= cells && std::abs(y) <= cells;
}

double latticeScore(const std::vector<const LatticeScorer*>& scorers, int a, int x, int y) {
  double sum = 0, total = 0;
  for (const LatticeScorer* s : scorers) {
    sum += s->score(0, a, x, y);
    total += s->maxScore();
  }
  return total > 0 ? sum / total : 0.0;
}

int searchLevels(int cells, int max_levels) {
  int levels = 0;
  while ((1 << levels) < 2 * cells + 1 && levels < max_levels) ++levels;
  return levels;
}

namespace {

struct Node {
  int a = 0, x = 0, y = 0;  // heading index; lower corner of the node's cells
  double score = 0;         // summed score (an upper bound above level 0)
};

// Branch and bound over the lattice, depth first, best child first: a node's bound below the
// best leaf so far prunes it and all it stands for.
class BranchAndBound {
 public:
  // `period`: headings in a full turn when the lattice spans one (its ends are neighbours), else 0.
  BranchAndBound(const std::vector<const LatticeScorer*>& scorers, int cells, int angles,
                 int levels, int period)
      : scorers_(scorers), cells_(cells), angles_(angles), levels_(levels), period_(period) {}

  // The motion prior's penalty (SearchOptions::prior_margin), in summed-score units.
  void setPrior(const SearchOptions& o, double resolution, double angular_step, double total) {
    if (!(o.prior_margin > 0) || !(o.prior_cap > 0)) return;
    penalty_ = o.prior_margin * total / o.prior_cap;
    cap_ = o.prior_cap;
    cell_information_ = o.prior_translation * resolution * resolution;
    heading_information_ = o.prior_rotation * angular_step * angular_step;
  }

  // The best leaf scoring above `threshold` (score < 0: none); leaves within `radius` cells and
  // `turn` headings of `center` are skipped; with `first`, the first leaf found above it.
  Node run(double threshold, bool first, const Node* center = nullptr, double radius = 0,
           int turn = 0) {
    center_ = center;
    radius_ = radius;
    turn_ = turn;
    first_ = first;
    done_ = false;
    threshold_ = threshold;
    int top = 0;
    while ((1 << top) < 2 * cells_ + 1 && top < levels_) ++top;
    const int w = 1 << top;
    std::vector<Node> roots;
    for (int a = -angles_; a <= angles_; ++a)
      for (int x = -cells_; x <= cells_; x += w)
        for (int y = -cells_; y <= cells_; y += w) roots.push_back(Node{a, x, y, 0});
    Node best{0, 0, 0, -1};
    best_ = &best;
    expand(roots, top);
    return best;
  }
  int leaves() const { return leaves_; }

 private:
  double score(int level, const Node& n) const {
    double sum = 0;
    for (const LatticeScorer* s : scorers_) sum += s->score(level, n.a, n.x, n.y);
    return sum - penalty(n, 1 << level);
  }
  // The prior's penalty at the node's pose nearest the center (a bound from below, as the
  // scores' is from above, so branch and bound stays exact). A lattice pose stands for the
  // poses of its cell and heading step, which the solve refines to: its nearest point counts,
  // so a prior narrower than a cell does not judge the cells next to the center as far.
  double penalty(const Node& n, int size) const {
    if (penalty_ == 0) return 0;
    const auto gap = [](int lo, int hi) {
      return std::max(0.0, (lo > 0 ? lo : hi < 0 ? -hi : 0) - 0.5);
    };
    const double gx = gap(n.x, n.x + size - 1), gy = gap(n.y, n.y + size - 1), ga = gap(n.a, n.a);
    const double m2 = (gx * gx + gy * gy) * cell_information_ + ga * ga * heading_information_;
    return penalty_ * std::min(m2, cap_);
  }
  // Whether every pose of the node lies within the excluded neighbourhood.
  bool excluded(const Node& n, int size) const {
    if (!center_) return false;
    int turned = std::abs(n.a - center_->a);
    if (period_ > 0) turned = std::min(turned, std::abs(period_ - turned));
    if (turned > turn_) return false;
    for (int dx : {0, size - 1})
      for (int dy : {0, size - 1}) {
        const double ex = n.x + dx - center_->x, ey = n.y + dy - center_->y;
        if (ex * ex + ey * ey > radius_ * radius_) return false;
      }
    return true;
  }
  void expand(std::vector<Node>& nodes, int level) {
    const int size = 1 << level;
    for (Node& n : nodes) n.score = excluded(n, size) ? -1 : score(level, n);
    std::sort(nodes.begin(), nodes.end(),
              [](const Node& a, const Node& b) { return a.score > b.score; });
    for (const Node& n : nodes) {
      if (done_ || n.score <= threshold_) return;
      if (level == 0) {
        ++leaves_;
        *best_ = n;
        threshold_ = n.score;
        done_ = first_;
        continue;
      }
      const int half = size / 2;
      std::vector<Node> children;
      children.reserve(4);
      for (int dx : {0, half})
        for (int dy : {0, half})
          if (n.x + dx <= cells_ && n.y + dy <= cells_)
            children.push_back(Node{n.a, n.x + dx, n.y + dy, 0});
      expand(children, level - 1);
    }
  }

  const std::vector<const LatticeScorer*>& scorers_;
  int cells_, angles_, levels_, period_;
  const Node* center_ = nullptr;
  double radius_ = 0;
  int turn_ = 0;
  double penalty_ = 0, cap_ = 0, cell_information_ = 0, heading_information_ = 0;
  bool first_ = false, done_ = false;
  double threshold_ = 0;
  Node* best_ = nullptr;
  int leaves_ = 0;
};

}  // namespace

template <class S>
SearchResult<S> correlativeSearch(const std::vector<const LatticeScorer*>& scorers,
                                  const SearchLattice<S>& lattice, const SearchOptions& options) {
  SearchResult<S> r;
  double total = 0;
  for (const LatticeScorer* s : scorers) total += s->maxScore();
  if (scorers.empty() || !(total > 0)) return r;
  // A search over a full turn meets the same heading at both ends of its range: a pose there is
  // no rival of itself.
  const int period =
      lattice.angular_step > 0 && (2 * lattice.angles + 1) * lattice.angular_step >= 2 * M_PI
          ? static_cast<int>(std::lround(2 * M_PI / lattice.angular_step))
          : 0;
  BranchAndBound search(scorers, lattice.cells, lattice.angles, lattice.levels, period);
  search.setPrior(options, lattice.resolution, lattice.angular_step, total);
  // Scores are compared as sums; a threshold just below s * total admits a sum of s * total.
  const auto below = [total](double s) { return s * total * (1 - 1e-12) - 1e-9; };
  const Node best = search.run(below(options.min_score), false);
  r.leaves = search.leaves();
  if (best.score < 0) return r;
  r.found = true;
  r.pose = lattice.pose(best.a, best.x, best.y);
  r.score = best.score / total;
  if (options.ambiguity_margin > 0) {
    const double radius = options.distinct_translation / lattice.resolution;
    const int turn =
        lattice.angular_step > 0
            ? static_cast<int>(std::floor(options.distinct_rotation / lattice.angular_step))
            : 0;
    const Node rival =
        search.run(below(r.score - options.ambiguity_margin), true, &best, radius, turn);
    r.leaves = search.leaves();
    if (rival.score >= 0) {
      r.ambiguous = true;
      r.rival = lattice.pose(rival.a, rival.x, rival.y);
      r.rival_score = rival.score / total;
    }
  }
  return r;
}

template <class S>
ScoringSlice<S>::~ScoringSlice() = default;

template struct SearchLattice<Space2D>;
template struct SearchLattice<Space3D>;
template class ScoringSlice<Space2D>;
template class ScoringSlice<Space3D>;
template SearchResult<Space2D> correlativeSearch(const std::vector<const LatticeScorer*>&,
                                                 const SearchLattice<Space2D>&,
                                                 const SearchOptions&);
template SearchResult<Space3D> correlativeSearch(const std::vector<const LatticeScorer*>&,
                                                 const SearchLattice<Space3D>&,
                                                 const SearchOptions&);

}  // namespace abi_v1
}  // namespace plugslam
