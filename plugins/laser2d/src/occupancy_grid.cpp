#include "occupancy_grid.h"

#include <cmath>
#include <cstdlib>

#include "plugslam/errors.h"

namespace plugslam {
namespace laser2d {

OccupancyGrid::OccupancyGrid(double resolution, const Eigen::Vector2d& min,
                             const Eigen::Vector2d& max)
    : resolution_(resolution) {
  if (!(resolution > 0) || !std::isfinite(resolution))
    throw InputError("occupancy grid: resolution must be > 0, got " + std::to_string(resolution));
  if (!min.allFinite() || !max.allFinite() || (max.array() < min.array()).any())
    throw InputError("occupancy grid: expected finite bounds with min <= max");
  origin_ = (min / resolution).array().floor().matrix() * resolution;
  const Eigen::Vector2d size = (max - origin_) / resolution;
  const double cells = (std::floor(size.x()) + 1) * (std::floor(size.y()) + 1);
  if (cells > 4e8)
    throw InputError("occupancy grid: " + std::to_string(cells) +
                     " cells is too large; increase resolution or lower max_range");
  width_ = static_cast<int>(std::floor(size.x())) + 1;
  height_ = static_cast<int>(std::floor(size.y())) + 1;
  cells_.assign(static_cast<size_t>(width_) * height_, 0.0f);
}

Eigen::Vector2i OccupancyGrid::cellOf(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d c = (p - origin_) / resolution_;
  return Eigen::Vector2i(static_cast<int>(std::floor(c.x())), static_cast<int>(std::floor(c.y())));
}

void OccupancyGrid::add(int x, int y, double v) {
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  float& c = cells_[static_cast<size_t>(y) * width_ + x];
  double next = c + v;
  if (next > clamp_log_odds) next = clamp_log_odds;
  if (next < -clamp_log_odds) next = -clamp_log_odds;
  // Exactly zero means "never observed": keep observed cells off it.
  if (next == 0.0) next = v > 0 ? 1e-6 : -1e-6;
  c = static_cast<float>(next);
}

void OccupancyGrid::traceRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                             bool hit_is_return) {
  // The end cell is excluded from the free updates.
  walkRay(cellOf(from), cellOf(to), [&](int x, int y, bool last) {
    add(x, y, !last ? miss_log_odds : (hit_is_return ? hit_log_odds : miss_log_odds));
  });
}

double OccupancyGrid::probability(int x, int y) const {
  return 1.0 - 1.0 / (1.0 + std::exp(logOdds(x, y)));
}

std::vector<uint8_t> OccupancyGrid::image() const {
  std::vector<uint8_t> px(static_cast<size_t>(width_) * height_);
  for (int y = 0; y < height_; ++y) {
    uint8_t* row = px.data() + static_cast<size_t>(height_ - 1 - y) * width_;
    for (int x = 0; x < width_; ++x) {
      if (unknown(x, y)) {
        row[x] = 205;
        continue;
      }
      const double p = probability(x, y);
      // map_server reads occupancy as (255 - value) / 255 with negate 0.
      row[x] = p > 0.65 ? 0 : (p < 0.196 ? 254 : 205);
    }
  }
  return px;
}

TiledOccupancyGrid::TiledOccupancyGrid(double resolution) : resolution_(resolution) {
  if (!(resolution > 0) || !std::isfinite(resolution))
    throw InputError("occupancy grid: resolution must be > 0, got " + std::to_string(resolution));
}

void TiledOccupancyGrid::clear() {
  tiles_.clear();
  last_tile_ = nullptr;
}

Eigen::Vector2i TiledOccupancyGrid::cellOf(const Eigen::Vector2d& p) const {
  return Eigen::Vector2i(static_cast<int>(std::floor(p.x() / resolution_)),
                         static_cast<int>(std::floor(p.y() / resolution_)));
}

float& TiledOccupancyGrid::cell(int x, int y) {
  // Floor division, so negative cells land in negative tiles.
  const int tx = x >= 0 ? x / kTile : -((-x - 1) / kTile) - 1;
  const int ty = y >= 0 ? y / kTile : -((-y - 1) / kTile) - 1;
  const uint64_t key =
      (static_cast<uint64_t>(static_cast<uint32_t>(tx)) << 32) | static_cast<uint32_t>(ty);
  if (!last_tile_ || key != last_key_) {
    auto& tile = tiles_[key];
    if (!tile) {
      tile.reset(new float[kTile * kTile]());
      if (tiles_.size() == 1) min_ = max_ = Eigen::Vector2i(x, y);
    }
    last_key_ = key;
    last_tile_ = tile.get();
  }
  min_ = min_.cwiseMin(Eigen::Vector2i(x, y));
  max_ = max_.cwiseMax(Eigen::Vector2i(x, y));
  return last_tile_[static_cast<size_t>(y - ty * kTile) * kTile + (x - tx * kTile)];
}

void TiledOccupancyGrid::add(int x, int y, double v) {
  float& c = cell(x, y);
  double next = c + v;
  if (next > clamp_log_odds) next = clamp_log_odds;
  if (next < -clamp_log_odds) next = -clamp_log_odds;
  if (next == 0.0) next = v > 0 ? 1e-6 : -1e-6;  // zero means "never observed"
  c = static_cast<float>(next);
}

bool TiledOccupancyGrid::traceRay(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                                  bool hit_is_return) {
  constexpr double kLimit = 1e6;  // cells: keeps the lattice indices far from int overflow
  const Eigen::Vector2d a = from / resolution_, b = to / resolution_;
  if (!a.allFinite() || !b.allFinite() || a.cwiseAbs().maxCoeff() > kLimit ||
      b.cwiseAbs().maxCoeff() > kLimit)
    return false;
  walkRay(cellOf(from), cellOf(to), [&](int x, int y, bool last) {
    add(x, y, !last ? miss_log_odds : (hit_is_return ? hit_log_odds : miss_log_odds));
  });
  return true;
}

std::string encodePgm(const std::vector<uint8_t>& pixels, int width, int height) {
  std::string out = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
  out.append(reinterpret_cast<const char*>(pixels.data()), pixels.size());
  return out;
}

}  // namespace laser2d
}  // namespace plugslam
