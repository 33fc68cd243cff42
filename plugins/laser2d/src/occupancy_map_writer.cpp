#include "occupancy_map_writer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "occupancy_grid.h"
#include "plugslam/atomic_file.h"
#include "plugslam/geometry.h"
#include "plugslam/png.h"
#include "plugslam/pose_space.h"
#include "point_cloud2d.h"

namespace plugslam {
namespace laser2d {

void OccupancyMapWriter::begin(const std::string& out_dir) {
  out_dir_ = out_dir;
  scans_.clear();
  by_map_.clear();
  frames_ = 0;
  written_.clear();
  placed_ = 0;
  traced_.reset();
  traced_frames_ = 0;
  last_traced_valid_ = false;
  last_map_ = kNoMap;
}

OccupancyMapWriter::OccupancyMapWriter() {
  // The map on demand, mid-run: the shell's `do <name>.save`. The poses are the estimates each
  // frame got when it was processed (later loop closures are applied at the end of the run).
  addAction("save", "write the map now from the poses estimated so far",
            [this](const std::vector<std::string>&) {
              RunResult now;
              for (const auto& s : scans_)
                if (s.map != kNoMap &&
                    (now.trajectory.empty() || s.stamp > now.trajectory.endTime()))
                  now.trajectory.push_back(s.stamp,
                                           Space2D::to3D(se2(s.live[0], s.live[1], s.live[2])));
              end(now);
              return written_.empty() ? std::string("no map written (no scan placed yet)")
                                      : "wrote " + written_.front();
            });
}

bool OccupancyMapWriter::isNew(int64_t map, const double in_map[3]) const {
  auto it = by_map_.find(map);
  if (it == by_map_.end()) return true;
  if (max_scans_per_map() > 0 && it->second.size() >= static_cast<size_t>(max_scans_per_map()))
    return false;
  for (size_t i : it->second) {
    const double* q = scans_[i].in_map;
    if (std::hypot(q[0] - in_map[0], q[1] - in_map[1]) < min_distance() &&
        std::abs(normalizeAngle(q[2] - in_map[2])) < min_angle())
      return false;
  }
  return true;
}

void OccupancyMapWriter::trace(const PointCloud2D& cloud, const SE2& world) {
  if (!traced_) traced_ = std::make_unique<TiledOccupancyGrid>(resolution());
  const Eigen::Vector2d o = world * cloud.sensor_origin;
  const double max2 = max_range() * max_range();
  for (const auto& p : cloud.points) {
    if (max_range() > 0 && (p - cloud.sensor_origin).squaredNorm() > max2) continue;
    traced_->traceRay(o, world * p);
  }
}

std::vector<const PointCloud2D*> OccupancyMapWriter::cloudsOf(const Frame& frame) {
  std::vector<const PointCloud2D*> out;
  for (const auto& name : measurements()) {
    const PointCloud2D* cloud = frame.measurement.find<PointCloud2D>(name);
    if (cloud && !cloud->empty()) out.push_back(cloud);
  }
  if (!out.empty()) ++frames_;
  return out;
}

void OccupancyMapWriter::publishGrid(int64_t map, double stamp) {
  auto it = by_map_.find(map);
  if (it == by_map_.end() || !grid_channel_.wanted()) return;
  // The scans in the map's frame, copied: the grid is traced later, on the viewer's thread. A
  // viewer's cell is at least 10 cm: finer shows nothing more on a screen-sized map and costs
  // four times the bytes per halving.
  struct Scan {
    SE2 pose;
    Eigen::Vector2d origin;
    std::vector<float> xy;
  };
  auto scans = std::make_shared<std::vector<Scan>>();
  for (size_t i : it->second) {
    const KeptScan& k = scans_[i];
    scans->push_back(Scan{se2(k.in_map[0], k.in_map[1], k.in_map[2]),
                          Eigen::Vector2d(k.origin[0], k.origin[1]), k.xy});
  }
  view::Grid grid;
  grid.stamp = stamp;
  grid.frame = "map/" + std::to_string(map);
  const double resolution = std::max(this->resolution(), 0.1);
  grid.fill = [scans, resolution](view::Grid& g) {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d hi = -lo;
    for (const auto& s : *scans) {
      const Eigen::Vector2d o = s.pose * s.origin;
      lo = lo.cwiseMin(o);
      hi = hi.cwiseMax(o);
      for (size_t k = 0; k + 1 < s.xy.size(); k += 2) {
        const Eigen::Vector2d p = s.pose * Eigen::Vector2d(s.xy[k], s.xy[k + 1]);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    if (!(lo.x() <= hi.x())) return;
    OccupancyGrid occupancy(resolution, lo, hi);
    for (const auto& s : *scans) {
      const Eigen::Vector2d o = s.pose * s.origin;
      for (size_t k = 0; k + 1 < s.xy.size(); k += 2)
        occupancy.traceRay(o, s.pose * Eigen::Vector2d(s.xy[k], s.xy[k + 1]));
    }
    g.cell_size = resolution;
    g.width = occupancy.width();
    g.height = occupancy.height();
    g.pose = Eigen::Isometry3d::Identity();
    g.pose.translation() << occupancy.origin().x(), occupancy.origin().y(), 0;
    g.cells.resize(static_cast<size_t>(g.width) * g.height);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x)
        g.cells[static_cast<size_t>(y) * g.width + x] =
            occupancy.unknown(x, y)
                ? view::Grid::kUnknown
                : static_cast<uint8_t>(std::lround(100 * occupancy.probability(x, y)));
  };
  grid_channel_.publish(std::move(grid), map);
}

void OccupancyMapWriter::consume(const Frame& frame) {
  // A new local map: the last one is complete, and its grid goes to viewers.
  if (frame.estimate.valid && frame.estimate.local_map != last_map_) {
    if (last_map_ != kNoMap) publishGrid(last_map_, frame.stamp);
    last_map_ = frame.estimate.local_map;
  }
  const bool estimated = frame.estimate.valid;
  if (estimated && frame.estimate.frozen) {
    // Its world pose is final: draw it now, keep nothing. A frame too close to the last one
    // drawn adds little and would cost a ray trace per frame (a robot standing still); a frame
    // the localization lost is only a guess (a lost robot would paint its drift forever).
    const SE2 world = Space2D::from3D(frame.estimate.world);
    const double at[3] = {world.translation().x(), world.translation().y(),
                          angleOf(world.linear())};
    const bool moved =
        !frame.estimate.lost &&
        (!last_traced_valid_ ||
         std::hypot(at[0] - last_traced_[0], at[1] - last_traced_[1]) >= min_distance() ||
         std::abs(normalizeAngle(at[2] - last_traced_[2])) >= min_angle());
    const std::vector<const PointCloud2D*> clouds = cloudsOf(frame);
    if (moved)
      for (const PointCloud2D* cloud : clouds) trace(*cloud, world);
    if (!clouds.empty() && moved) {
      ++traced_frames_;
      last_traced_valid_ = true;
      std::copy(at, at + 3, last_traced_);
    }
    return;
  }
  const SE2 in_map = Space2D::from3D(frame.estimate.in_map);
  const double pose[3] = {in_map.translation().x(), in_map.translation().y(),
                          angleOf(in_map.linear())};
  const SE2 world = Space2D::from3D(frame.estimate.world);
  for (const PointCloud2D* cloud : cloudsOf(frame)) {
    // Several entries of one frame are kept together (the test sees the first one only).
    // Without an estimate there is nothing to compare: kept (the trajectory may place it).
    if (estimated && !isNew(frame.estimate.local_map, pose) &&
        !(!scans_.empty() && scans_.back().seq == frame.seq))
      continue;
    KeptScan kept{frame.stamp,
                  frame.seq,
                  {static_cast<float>(cloud->sensor_origin.x()),
                   static_cast<float>(cloud->sensor_origin.y())},
                  {},
                  estimated ? frame.estimate.local_map : kNoMap,
                  {pose[0], pose[1], pose[2]},
                  {world.translation().x(), world.translation().y(), angleOf(world.linear())}};
    kept.xy.reserve(2 * cloud->size());
    const double max2 = max_range() * max_range();
    for (const auto& p : cloud->points) {
      if (max_range() > 0 && (p - cloud->sensor_origin).squaredNorm() > max2) continue;
      kept.xy.push_back(static_cast<float>(p.x()));
      kept.xy.push_back(static_cast<float>(p.y()));
    }
    if (estimated) by_map_[kept.map].push_back(scans_.size());
    scans_.push_back(std::move(kept));
  }
}

void OccupancyMapWriter::end(const RunResult& result) {
  if (last_map_ != kNoMap) publishGrid(last_map_, result.trajectory.empty() ? 0 : result.trajectory.endTime());
  written_.clear();
  placed_ = 0;
  // Place every kept scan at its corrected pose.
  struct Placed {
    const KeptScan* scan;
    SE2 pose;
  };
  std::vector<Placed> placed;
  placed.reserve(scans_.size());
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  // A run that saw no frame (sessions merged or loaded) has only its local maps: each map's
  // clouds are drawn as one scan from where its sensor was, at the map's corrected origin.
  std::vector<KeptScan> from_maps;
  std::vector<SE2> map_poses;
  if (scans_.empty() && frames_ == 0) {
    for (const auto& m : result.local_maps) {
      if (m->dimension != 2) continue;
      for (const std::string& entry : m->scene.names()) {
        if (!m->scene.holds<PointCloud2D>(entry)) continue;
        const PointCloud2D& cloud = m->scene.get<PointCloud2D>(entry);
        KeptScan k{};
        k.origin[0] = static_cast<float>(cloud.sensor_origin.x());
        k.origin[1] = static_cast<float>(cloud.sensor_origin.y());
        for (const auto& p : cloud.points) {
          k.xy.push_back(static_cast<float>(p.x()));
          k.xy.push_back(static_cast<float>(p.y()));
        }
        from_maps.push_back(std::move(k));
        map_poses.push_back(Space2D::from3D(m->origin));
      }
    }
  }
  for (size_t i = 0; i < scans_.size() + from_maps.size(); ++i) {
    const bool kept = i < scans_.size();
    const KeptScan& s = kept ? scans_[i] : from_maps[i - scans_.size()];
    SE2 pose = SE2::Identity();
    if (kept) {
      const auto at = result.trajectory.nearest(s.stamp, max_time_offset());
      if (!at) continue;
      pose = Space2D::from3D(result.trajectory[*at].pose);
    } else {
      pose = map_poses[i - scans_.size()];
    }
    placed.push_back({&s, pose});
    const Eigen::Vector2d o = pose * Eigen::Vector2d(s.origin[0], s.origin[1]);
    lo = lo.cwiseMin(o);
    hi = hi.cwiseMax(o);
    for (size_t k = 0; k + 1 < s.xy.size(); k += 2) {
      const Eigen::Vector2d p = pose * Eigen::Vector2d(s.xy[k], s.xy[k + 1]);
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  const bool traced = traced_ && !traced_->empty();
  if (placed.empty() && !traced) {
    spdlog::warn(
        "{}: no scan could be placed on the trajectory ({} kept, {} poses); no map written",
        name().empty() ? typeName() : name(), scans_.size(), result.trajectory.size());
    return;
  }
  if (traced) {
    // Cell centres: the dense grid below is on the same lattice (origin a multiple of the cell).
    const double r = traced_->resolution();
    lo = lo.cwiseMin((traced_->minCell().cast<double>().array() + 0.5).matrix() * r);
    hi = hi.cwiseMax((traced_->maxCell().cast<double>().array() + 0.5).matrix() * r);
  }
  // The traced frames' lattice decides when there are some (a `resolution` set mid-run).
  const double resolution = traced ? traced_->resolution() : this->resolution();
  const double margin = 2 * resolution;
  OccupancyGrid grid(resolution, lo - Eigen::Vector2d::Constant(margin),
                     hi + Eigen::Vector2d::Constant(margin));
  if (traced) {
    const Eigen::Vector2i offset((grid.origin() / grid.resolution()).array().round().cast<int>());
    traced_->forEachCell([&](int x, int y, double log_odds) {
      grid.addLogOdds(x - offset.x(), y - offset.y(), log_odds);
    });
  }
  for (const auto& p : placed) {
    const Eigen::Vector2d o = p.pose * Eigen::Vector2d(p.scan->origin[0], p.scan->origin[1]);
    const auto& xy = p.scan->xy;
    for (size_t k = 0; k + 1 < xy.size(); k += 2)
      grid.traceRay(o, p.pose * Eigen::Vector2d(xy[k], xy[k + 1]));
  }
  placed_ = placed.size();

  const std::string base = !file().empty() && file()[0] == '/'
                               ? file()
                               : (out_dir_.empty() ? "." : out_dir_) + "/" + file();
  const std::string image_name = base.substr(base.find_last_of('/') + 1) + ".pgm";
  const std::vector<uint8_t> pixels = grid.image();
  const std::string pgm = encodePgm(pixels, grid.width(), grid.height());
  PngPixels image;
  image.data = pixels.data();
  image.width = grid.width();
  image.height = grid.height();
  // A map is mostly large flat areas: row filters buy little there and cost time. One IDAT
  // chunk keeps map.png byte for byte what the writer always produced.
  PngOptions flat;
  flat.filters = false;
  flat.idat_bytes = 0;
  const std::string png = encodePng(image, flat);
  std::ostringstream yaml;
  yaml.precision(10);
  yaml << "image: " << image_name << "\n"
       << "resolution: " << grid.resolution() << "\n"
       << "origin: [" << grid.origin().x() << ", " << grid.origin().y() << ", 0.0]\n"
       << "negate: 0\n"
       << "occupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n";
  const std::string yaml_text = yaml.str();
  auto write = [&](const std::string& path, const std::string& bytes) {
    writeFileAtomically(path, [&](std::ostream& out) { out.write(bytes.data(), bytes.size()); });
    written_.push_back(path);
  };
  write(base + ".pgm", pgm);
  write(base + ".yaml", yaml_text);
  write(base + ".png", png);
}

}  // namespace laser2d
}  // namespace plugslam
