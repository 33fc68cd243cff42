#include "correlative_matcher.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "plugslam/errors.h"

namespace plugslam {
namespace laser2d {
namespace {

constexpr int kBlurCells = 2;  // gaussian of sigma = one cell, cut at two cells

int floorCell(double v) { return static_cast<int>(std::floor(v)); }

}  // namespace

CorrelativeGrid::CorrelativeGrid(const std::vector<Eigen::Vector2d>& points,
                                 const std::vector<Eigen::Vector2d>& normals, double extent,
                                 double resolution, int levels, const Eigen::Vector2d& clip_min,
                                 const Eigen::Vector2d& clip_max)
    : resolution_(resolution) {
  Eigen::Vector2d lo = clip_max, hi = clip_min;
  for (const auto& p : points) {
    if ((p.array() < clip_min.array()).any() || (p.array() > clip_max.array()).any()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if ((lo.array() > hi.array()).any()) lo = hi = 0.5 * (clip_min + clip_max);  // nothing inside
  origin_ = lo - Eigen::Vector2d::Constant((kBlurCells + 1) * resolution);
  width_ = floorCell((hi.x() - origin_.x()) / resolution) + kBlurCells + 2;
  height_ = floorCell((hi.y() - origin_.y()) / resolution) + kBlurCells + 2;

  levels_.resize(static_cast<size_t>(std::max(levels, 0)) + 1);
  Level& base = levels_[0];
  base.width = width_;
  base.height = height_;
  base.cells.assign(static_cast<size_t>(width_) * height_, 0);
  // Hit cells first: a point with a normal stands for a patch of wall `extent` either side of it
  // along its tangent, so the gaps between a far wall's sparse points still score.
  std::vector<uint8_t> hit(base.cells.size(), 0);
  const auto mark = [&](const Eigen::Vector2d& q) {
    const int x = floorCell((q.x() - origin_.x()) / resolution);
    const int y = floorCell((q.y() - origin_.y()) / resolution);
    if (x >= 0 && y >= 0 && x < width_ && y < height_) hit[static_cast<size_t>(y) * width_ + x] = 1;
  };
  const bool splat = extent > 0 && normals.size() == points.size();
  const int samples = splat ? static_cast<int>(std::ceil(2 * extent / resolution)) : 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points[i];
    if ((p.array() < clip_min.array()).any() || (p.array() > clip_max.array()).any()) continue;
    mark(p);
    if (samples == 0) continue;
    const Eigen::Vector2d tangent(-normals[i].y(), normals[i].x());
    for (int k = 0; k <= samples; ++k) mark(p + (-extent + 2 * extent * k / samples) * tangent);
  }
  // Then a gaussian of one cell around every hit cell (by cell distance).
  uint8_t kernel[2 * kBlurCells + 1][2 * kBlurCells + 1];
  for (int dy = -kBlurCells; dy <= kBlurCells; ++dy)
    for (int dx = -kBlurCells; dx <= kBlurCells; ++dx)
      kernel[dy + kBlurCells][dx + kBlurCells] =
          static_cast<uint8_t>(std::lround(255 * std::exp(-0.5 * (dx * dx + dy * dy))));
  for (int cy = 0; cy < height_; ++cy) {
    for (int cx = 0; cx < width_; ++cx) {
      if (!hit[static_cast<size_t>(cy) * width_ + cx]) continue;
      for (int y = std::max(cy - kBlurCells, 0); y <= std::min(cy + kBlurCells, height_ - 1); ++y)
        for (int x = std::max(cx - kBlurCells, 0); x <= std::min(cx + kBlurCells, width_ - 1);
             ++x) {
          uint8_t& cell = base.cells[static_cast<size_t>(y) * width_ + x];
          cell = std::max(cell, kernel[y - cy + kBlurCells][x - cx + kBlurCells]);
        }
    }
  }
  pool();
}

CorrelativeGrid::CorrelativeGrid(double resolution, const Eigen::Vector2d& origin, int width,
                                 int height, std::vector<uint8_t> base, int levels, uint8_t outside)
    : resolution_(resolution), origin_(origin), width_(width), height_(height), outside_(outside) {
  if (width <= 0 || height <= 0 || base.size() != static_cast<size_t>(width) * height)
    throw InputError("correlative grid: " + std::to_string(base.size()) + " cells given for " +
                     std::to_string(width) + " x " + std::to_string(height));
  levels_.resize(static_cast<size_t>(std::max(levels, 0)) + 1);
  levels_[0].width = width_;
  levels_[0].height = height_;
  levels_[0].cells = std::move(base);
  pool();
}

void CorrelativeGrid::pool() {
  // Level h from level h-1: the 2^h window at c is the union of four 2^(h-1) windows.
  for (size_t h = 1; h < levels_.size(); ++h) {
    const int s = 1 << (h - 1);
    Level& l = levels_[h];
    l.offset = (1 << h) - 1;
    l.width = width_ + l.offset;
    l.height = height_ + l.offset;
    l.cells.assign(static_cast<size_t>(l.width) * l.height, 0);
    const int lv = static_cast<int>(h) - 1;
    for (int yi = 0; yi < l.height; ++yi) {
      const int y = yi - l.offset;
      for (int xi = 0; xi < l.width; ++xi) {
        const int x = xi - l.offset;
        const int v = std::max(std::max(value(lv, x, y), value(lv, x + s, y)),
                               std::max(value(lv, x, y + s), value(lv, x + s, y + s)));
        l.cells[static_cast<size_t>(yi) * l.width + xi] = static_cast<uint8_t>(v);
      }
    }
  }
}

std::vector<Eigen::Vector2d> voxelFilter(const std::vector<Eigen::Vector2d>& points,
                                         double resolution) {
  std::unordered_set<uint64_t> seen;
  std::vector<Eigen::Vector2d> out;
  out.reserve(points.size());
  for (const auto& p : points) {
    const auto x = static_cast<uint32_t>(static_cast<int32_t>(std::floor(p.x() / resolution)));
    const auto y = static_cast<uint32_t>(static_cast<int32_t>(std::floor(p.y() / resolution)));
    if (seen.insert((static_cast<uint64_t>(x) << 32) | y).second) out.push_back(p);
  }
  return out;
}

namespace {

struct Candidate {
  int angle = 0, x = 0, y = 0;  // angle index; cell offset of the region's lower corner
  int64_t score = 0;            // sum of grid values (upper bound above level 0)
};

// Branch and bound over the discretized poses: the query's points are rotated and discretized
// once per angle; a candidate at level h stands for 2^h x 2^h offsets and its score on the
// level-h grid bounds theirs from above.
class Search {
 public:
  Search(const CorrelativeGrid& grid, const std::vector<Eigen::Vector2d>& query, const SE2& guess,
         const CorrelativeOptions& o)
      : grid_(grid), n_(static_cast<int64_t>(query.size())) {
    const double r = grid.resolution();
    double range = 0;
    for (const auto& q : query) range = std::max(range, q.norm());
    step_ = o.angular_step;
    if (step_ <= 0) {
      // One cell of arc at the farthest point (Hess et al., eq. 7).
      const double c = 1 - r * r / (2 * std::max(range, r) * std::max(range, r));
      step_ = std::acos(std::max(c, -1.0));
    }
    const int half_angles = static_cast<int>(std::ceil(o.angular_window / step_ - 1e-9));
    window_ = static_cast<int>(std::ceil(o.linear_window / r - 1e-9));
    const double theta0 = std::atan2(guess.linear()(1, 0), guess.linear()(0, 0));
    const Eigen::Vector2d t0 = guess.translation();
    for (int k = -half_angles; k <= half_angles; ++k) {
      const double theta = theta0 + k * step_;
      const Eigen::Rotation2Dd rot(theta);
      std::vector<Eigen::Vector2i> cells(query.size());
      for (size_t i = 0; i < query.size(); ++i) {
        const Eigen::Vector2d p = t0 + rot * query[i] - grid.origin();
        cells[i] = Eigen::Vector2i(floorCell(p.x() / r), floorCell(p.y() / r));
      }
      thetas_.push_back(theta);
      scans_.push_back(std::move(cells));
    }
    t0_ = t0;
  }

  double step() const { return step_; }
  int angles() const { return static_cast<int>(thetas_.size()); }
  int leaves() const { return leaves_; }
  double toScore(int64_t sum) const { return n_ ? static_cast<double>(sum) / (255.0 * n_) : 0; }
  SE2 pose(const Candidate& c) const {
    const double r = grid_.resolution();
    return se2(t0_.x() + c.x * r, t0_.y() + c.y * r, thetas_[static_cast<size_t>(c.angle)]);
  }

  // Best leaf scoring above `threshold` (score -1 when none); with `first`, the first such leaf.
  // Leaves within `exclusion` of `center` are skipped.
  Candidate run(int64_t threshold, bool first, const Candidate* center = nullptr,
                double exclusion_cells = 0, int exclusion_angles = 0) {
    center_ = center;
    exclusion_cells_ = exclusion_cells;
    exclusion_angles_ = exclusion_angles;
    first_ = first;
    done_ = false;
    int top = 0;
    while ((1 << top) < 2 * window_ + 1 && top < grid_.levels()) ++top;
    std::vector<Candidate> roots;
    const int w = 1 << top;
    for (int a = 0; a < angles(); ++a)
      for (int x = -window_; x <= window_; x += w)
        for (int y = -window_; y <= window_; y += w) roots.push_back(Candidate{a, x, y, 0});
    Candidate best{0, 0, 0, -1};
    best_ = &best;
    threshold_ = threshold;
    expand(roots, top);
    return best;
  }

 private:
  int64_t score(int level, const Candidate& c) const {
    int64_t sum = 0;
    for (const auto& p : scans_[static_cast<size_t>(c.angle)])
      sum += grid_.value(level, p.x() + c.x, p.y() + c.y);
    return sum;
  }

  // True when every pose of the region lies within the exclusion zone.
  bool excluded(const Candidate& c, int size) const {
    if (!center_ || std::abs(c.angle - center_->angle) > exclusion_angles_) return false;
    const double r2 = exclusion_cells_ * exclusion_cells_;
    for (int dx : {0, size - 1})
      for (int dy : {0, size - 1}) {
        const double ex = c.x + dx - center_->x, ey = c.y + dy - center_->y;
        if (ex * ex + ey * ey > r2) return false;
      }
    return true;
  }

  void expand(std::vector<Candidate>& candidates, int level) {
    const int size = 1 << level;
    for (auto& c : candidates) c.score = excluded(c, size) ? -1 : score(level, c);
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    for (const auto& c : candidates) {
      if (done_ || c.score <= threshold_) return;
      if (level == 0) {
        ++leaves_;
        *best_ = c;
        threshold_ = c.score;
        done_ = first_;
        continue;
      }
      const int half = size / 2;
      std::vector<Candidate> children;
      children.reserve(4);
      for (int dx : {0, half})
        for (int dy : {0, half})
          if (c.x + dx <= window_ && c.y + dy <= window_)
            children.push_back(Candidate{c.angle, c.x + dx, c.y + dy, 0});
      expand(children, level - 1);
    }
  }

  const CorrelativeGrid& grid_;
  int64_t n_;
  double step_ = 0;
  int window_ = 0;
  Eigen::Vector2d t0_;
  std::vector<double> thetas_;
  std::vector<std::vector<Eigen::Vector2i>> scans_;
  const Candidate* center_ = nullptr;
  double exclusion_cells_ = 0;
  int exclusion_angles_ = 0;
  bool first_ = false, done_ = false;
  Candidate* best_ = nullptr;
  int64_t threshold_ = 0;
  int leaves_ = 0;
};

}  // namespace

CorrelativeMatch matchCorrelative(const CorrelativeGrid& grid,
                                  const std::vector<Eigen::Vector2d>& query, const SE2& guess,
                                  const CorrelativeOptions& options) {
  CorrelativeMatch m;
  if (query.empty()) return m;
  Search search(grid, query, guess, options);
  m.angular_step = search.step();
  m.angles = search.angles();
  const auto n = static_cast<int64_t>(query.size());
  // Sums are integers: a score threshold s becomes the sum just below s * 255 * n.
  const auto sumBelow = [n](double s) {
    return static_cast<int64_t>(std::ceil(s * 255.0 * static_cast<double>(n))) - 1;
  };
  const Candidate best = search.run(sumBelow(options.min_score), false);
  m.leaves = search.leaves();
  if (best.score < 0) return m;
  m.found = true;
  m.pose = search.pose(best);
  m.score = search.toScore(best.score);
  if (options.min_score_margin > 0) {
    const double cells = options.distinct_translation / grid.resolution();
    const int angles = static_cast<int>(std::floor(options.distinct_rotation / m.angular_step));
    const Candidate second =
        search.run(sumBelow(m.score - options.min_score_margin), true, &best, cells, angles);
    m.leaves = search.leaves();
    if (second.score >= 0) {
      m.ambiguous = true;
      m.second_score = search.toScore(second.score);
    }
  }
  return m;
}

}  // namespace laser2d
}  // namespace plugslam
