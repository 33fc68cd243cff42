#include "occupancy_grid.h"

#include <zlib.h>

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
  const Eigen::Vector2i a = cellOf(from), b = cellOf(to);
  // Bresenham over cells, the end cell excluded from the free updates.
  int x = a.x(), y = a.y();
  const int dx = std::abs(b.x() - x), dy = -std::abs(b.y() - y);
  const int sx = x < b.x() ? 1 : -1, sy = y < b.y() ? 1 : -1;
  int err = dx + dy;
  while (x != b.x() || y != b.y()) {
    add(x, y, miss_log_odds);
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
  add(b.x(), b.y(), hit_is_return ? hit_log_odds : miss_log_odds);
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

std::string encodePgm(const std::vector<uint8_t>& pixels, int width, int height) {
  std::string out = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
  out.append(reinterpret_cast<const char*>(pixels.data()), pixels.size());
  return out;
}

namespace {
void putU32(std::string& s, uint32_t v) {
  s.push_back(static_cast<char>(v >> 24));
  s.push_back(static_cast<char>(v >> 16));
  s.push_back(static_cast<char>(v >> 8));
  s.push_back(static_cast<char>(v));
}

void chunk(std::string& out, const char* type, const std::string& data) {
  putU32(out, static_cast<uint32_t>(data.size()));
  const std::string body = std::string(type, 4) + data;
  out += body;
  putU32(out, static_cast<uint32_t>(
                  crc32(0, reinterpret_cast<const Bytef*>(body.data()), body.size())));
}
}  // namespace

std::string encodePng(const std::vector<uint8_t>& pixels, int width, int height) {
  if (width <= 0 || height <= 0 || pixels.size() != static_cast<size_t>(width) * height)
    throw InputError("PNG: expected width * height pixels");
  std::string raw;
  raw.reserve(static_cast<size_t>(width + 1) * height);
  for (int y = 0; y < height; ++y) {
    raw.push_back('\0');  // filter type: none
    raw.append(reinterpret_cast<const char*>(pixels.data()) + static_cast<size_t>(y) * width,
               width);
  }
  uLongf size = compressBound(raw.size());
  std::string deflated(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(deflated.data()), &size,
                reinterpret_cast<const Bytef*>(raw.data()), raw.size(), 6) != Z_OK)
    throw Error("PNG: zlib compression failed");
  deflated.resize(size);

  std::string out("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  putU32(ihdr, static_cast<uint32_t>(width));
  putU32(ihdr, static_cast<uint32_t>(height));
  ihdr += std::string("\x08\x00\x00\x00\x00", 5);  // 8-bit grayscale, deflate, no interlace
  chunk(out, "IHDR", ihdr);
  chunk(out, "IDAT", deflated);
  chunk(out, "IEND", "");
  return out;
}

}  // namespace laser2d
}  // namespace plugslam
