// Procedural textures. Every pattern is a closed-form function of the face coordinates plus one
// bilinear lookup in a periodic fBm noise tile, so shading a pixel costs tens of nanoseconds.
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sim3d/world.h"

namespace plugslam {
namespace sim {
namespace sim3d {
namespace {

constexpr int kTile = 256;  // noise tile side (power of two: wrapping is a mask)

inline uint32_t hash3(int64_t a, int64_t b, uint32_t seed) {
  uint32_t h = seed * 0x9E3779B1u ^ static_cast<uint32_t>(a) * 0x85EBCA77u ^
               static_cast<uint32_t>(b) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}

inline double unit(uint32_t h) { return (h >> 8) * (1.0 / 16777216.0); }

// Periodic fBm of five value-noise octaves (4 .. 64 lattice cells across the tile), in [0, 1].
std::vector<double> makeNoiseTile() {
  std::vector<double> tile(kTile * kTile, 0.0);
  double amplitude = 1.0;
  for (int cells = 4; cells <= 64; cells *= 2, amplitude *= 0.55) {
    const int period = kTile / cells;
    for (int y = 0; y < kTile; ++y) {
      const int cy = y / period;
      double fy = static_cast<double>(y % period) / period;
      fy = fy * fy * (3.0 - 2.0 * fy);
      for (int x = 0; x < kTile; ++x) {
        const int cx = x / period;
        double fx = static_cast<double>(x % period) / period;
        fx = fx * fx * (3.0 - 2.0 * fx);
        auto lattice = [&](int i, int j) {
          return unit(hash3(i % cells, j % cells, 0x51ED27u + static_cast<uint32_t>(cells)));
        };
        const double a = lattice(cx, cy), b = lattice(cx + 1, cy);
        const double c = lattice(cx, cy + 1), d = lattice(cx + 1, cy + 1);
        tile[y * kTile + x] +=
            amplitude * ((a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy);
      }
    }
  }
  const auto [lo, hi] = std::minmax_element(tile.begin(), tile.end());
  const double l = *lo, r = *hi - *lo;
  for (double& v : tile) v = (v - l) / r;
  return tile;
}

const std::vector<double>& noiseTile() {
  static const std::vector<double> tile = makeNoiseTile();
  return tile;
}

// Bilinear lookup, coordinates in tile texels, wrapping.
inline double noise(double x, double y) {
  const std::vector<double>& tile = noiseTile();
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const double fx = x - fx0, fy = y - fy0;
  const int x0 = static_cast<int>(static_cast<int64_t>(fx0) & (kTile - 1));
  const int y0 = static_cast<int>(static_cast<int64_t>(fy0) & (kTile - 1));
  const int x1 = (x0 + 1) & (kTile - 1), y1 = (y0 + 1) & (kTile - 1);
  const double a = tile[y0 * kTile + x0], b = tile[y0 * kTile + x1];
  const double c = tile[y1 * kTile + x0], d = tile[y1 * kTile + x1];
  return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy;
}

inline double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

const std::array<Eigen::Vector3d, 8>& palette() {
  static const std::array<Eigen::Vector3d, 8> p = {
      Eigen::Vector3d(0.85, 0.20, 0.15), Eigen::Vector3d(0.15, 0.35, 0.75),
      Eigen::Vector3d(0.95, 0.80, 0.20), Eigen::Vector3d(0.20, 0.60, 0.30),
      Eigen::Vector3d(0.95, 0.95, 0.92), Eigen::Vector3d(0.10, 0.10, 0.12),
      Eigen::Vector3d(0.60, 0.35, 0.65), Eigen::Vector3d(0.90, 0.55, 0.25)};
  return p;
}

}  // namespace

namespace {

// The pattern's smallest feature [m] and its average colour: when a pixel covers more than
// about a feature, the detail would alias into noise that flickers from frame to frame (and
// gives detectors features that are not on the surface), so it fades to the average.
void lodOf(const Material& m, double* feature, Eigen::Vector3d* mean) {
  switch (m.pattern) {
    case Pattern::kChecker:
      *feature = m.scale;
      *mean = 0.5 * (m.color_a + m.color_b);
      return;
    case Pattern::kBricks:
      *feature = m.scale / 3.0;
      *mean = 0.8 * m.color_a + 0.155 * m.color_b;
      return;
    case Pattern::kNoise:
      *feature = 0.25 * m.scale;
      *mean = 0.5 * (m.color_a + m.color_b);
      return;
    case Pattern::kWindows:
      *feature = 0.2 * m.scale;
      *mean = 0.7 * m.color_a + 0.3 * m.color_b;
      return;
    case Pattern::kPlanks:
      *feature = 0.2 * m.scale;
      *mean = 0.95 * (0.75 * m.color_a + 0.25 * m.color_b);
      return;
    case Pattern::kTiles:
      *feature = 0.2 * m.scale;
      *mean = 0.9 * 0.95 * m.color_a + 0.1 * m.color_b;
      return;
    case Pattern::kPoster:
      *feature = m.scale;
      *mean = Eigen::Vector3d(0.5875, 0.4875, 0.4175);
      return;
    case Pattern::kPlain:
      *feature = 1e9;
      *mean = m.color_a;
      return;
  }
  *feature = 1e9;
  *mean = m.color_a;
}

Eigen::Vector3d detail(const Material& m, double s, double t);

}  // namespace

Eigen::Vector3d albedo(const Material& m, double s, double t, const Eigen::Vector3d& p,
                       double footprint) {
  if (m.world_uv) {
    s = p.x();
    t = p.y();
  }
  if (footprint <= 0.0) return detail(m, s, t);
  double feature;
  Eigen::Vector3d mean;
  lodOf(m, &feature, &mean);
  const double k = smoothstep(0.3, 1.0, footprint / feature);
  if (k >= 1.0) return mean;
  if (k <= 0.0) return detail(m, s, t);
  return (1.0 - k) * detail(m, s, t) + k * mean;
}

namespace {

Eigen::Vector3d detail(const Material& m, double s, double t) {
  const double x = s / m.scale, y = t / m.scale;
  // Each seed looks at another part of the noise tile.
  const double ox = (m.seed & 0xFFu) * 7.31, oy = ((m.seed >> 8) & 0xFFu) * 5.17;
  const double n = noise(16.0 * x + ox, 16.0 * y + oy);
  switch (m.pattern) {
    case Pattern::kChecker: {
      const bool odd =
          ((static_cast<int64_t>(std::floor(x)) + static_cast<int64_t>(std::floor(y))) & 1) != 0;
      return (odd ? m.color_b : m.color_a) * (0.8 + 0.4 * n);
    }
    case Pattern::kBricks: {
      const double by = y * 3.0;  // bricks are a third as tall as long
      const int64_t row = static_cast<int64_t>(std::floor(by));
      const double bx = x + ((row & 1) ? 0.5 : 0.0);
      const int64_t col = static_cast<int64_t>(std::floor(bx));
      const double fx = bx - col, fy = by - row;
      if (fx < 0.04 || fy < 0.12) return m.color_b * (0.85 + 0.3 * n);
      const double tone = 0.65 + 0.6 * unit(hash3(col, row, m.seed));
      return m.color_a * tone * (0.85 + 0.3 * n);
    }
    case Pattern::kNoise: {
      const double k = smoothstep(0.35, 0.65, n);
      return m.color_a * (1.0 - k) + m.color_b * k;
    }
    case Pattern::kWindows: {
      const double wy = y / 1.3;
      const int64_t col = static_cast<int64_t>(std::floor(x)),
                    row = static_cast<int64_t>(std::floor(wy));
      const double fx = x - col, fy = wy - row;
      const Eigen::Vector3d wall = m.color_a * (0.85 + 0.3 * n);
      if (fx > 0.2 && fx < 0.8 && fy > 0.25 && fy < 0.8) {
        if (std::abs(fx - 0.5) < 0.02) return Eigen::Vector3d(0.9, 0.9, 0.9);  // mullion
        return m.color_b * (0.5 + unit(hash3(col, row, m.seed)));
      }
      return wall;
    }
    case Pattern::kPlanks: {
      const double py = y * 5.0;
      const int64_t row = static_cast<int64_t>(std::floor(py));
      const double px = x * 0.8 + 0.37 * row;
      const int64_t col = static_cast<int64_t>(std::floor(px));
      const double fx = px - col, fy = py - row;
      if (fx < 0.01 || fy < 0.05) return m.color_b;
      const double grain = noise(4.0 * x + ox, 64.0 * y + oy);
      const double tone = 0.7 + 0.5 * unit(hash3(col, row, m.seed));
      return (m.color_a * (1.0 - 0.5 * grain) + m.color_b * 0.5 * grain) * tone;
    }
    case Pattern::kTiles: {
      const int64_t col = static_cast<int64_t>(std::floor(x)),
                    row = static_cast<int64_t>(std::floor(y));
      const double fx = x - col, fy = y - row;
      if (fx < 0.05 || fy < 0.05) return m.color_b;
      return m.color_a * (0.75 + 0.4 * unit(hash3(col, row, m.seed))) * (0.9 + 0.2 * n);
    }
    case Pattern::kPoster: {
      const int64_t col = static_cast<int64_t>(std::floor(x)),
                    row = static_cast<int64_t>(std::floor(y));
      const uint32_t h = hash3(col, row, m.seed);
      return palette()[h & 7u] * (0.8 + 0.4 * n);
    }
    case Pattern::kPlain:
      return m.color_a * (0.9 + 0.2 * n);
  }
  return m.color_a;
}

}  // namespace

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
