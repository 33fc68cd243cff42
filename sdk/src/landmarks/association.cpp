#include "plugslam/landmarks/association.h"

#include <algorithm>
#include <cmath>

#include "plugslam/landmarks/observation_factor.h"

namespace plugslam {
inline namespace abi_v1 {

double predictedScale(double reference_distance, double distance, double max_scale) {
  if (!(reference_distance > 0) || !(distance > 0)) return 1.0;
  return std::clamp(reference_distance / distance, 1.0, std::max(1.0, max_scale));
}

void FeatureGrid::build(const FeatureSet& features, double cell) {
  features_ = &features;
  cell_ = cell > 1.0 ? cell : 1.0;
  cols_ = std::max(1, static_cast<int>(std::ceil(features.width / cell_)));
  rows_ = std::max(1, static_cast<int>(std::ceil(features.height / cell_)));
  const size_t cells = static_cast<size_t>(cols_) * static_cast<size_t>(rows_);
  std::vector<int> cell_of(features.size());
  start_.assign(cells + 1, 0);
  for (size_t i = 0; i < features.size(); ++i) {
    const int cx = std::clamp(static_cast<int>(features.pixels[i].x() / cell_), 0, cols_ - 1);
    const int cy = std::clamp(static_cast<int>(features.pixels[i].y() / cell_), 0, rows_ - 1);
    cell_of[i] = cy * cols_ + cx;
    ++start_[cell_of[i] + 1];
  }
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  order_.resize(features.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (size_t i = 0; i < features.size(); ++i) order_[fill[cell_of[i]]++] = static_cast<int>(i);
}

void FeatureGrid::associate(const LandmarkMap& map, const Eigen::Isometry3d& camera_in_scene,
                            const AssociationOptions& o, std::vector<LandmarkMatch>& matches,
                            std::vector<bool>* visible) const {
  matches.clear();
  if (visible) visible->assign(map.size(), false);
  if (!features_ || features_->empty() || map.empty()) return;
  const FeatureSet& f = *features_;
  const int bytes = f.descriptor_bytes;
  if (map.descriptor_bytes != bytes) return;  // different descriptors cannot be compared
  best_landmark_.assign(f.size(), -1);
  best_distance_.assign(f.size(), o.max_hamming + 1);
  const Eigen::Isometry3d to_camera = camera_in_scene.inverse();
  const bool scaled = f.max_scale > 1.0 && map.reference_distances.size() == map.size();
  const double umin = o.border, vmin = o.border;
  const double umax = f.width - 1 - o.border, vmax = f.height - 1 - o.border;
  for (size_t j = 0; j < map.size(); ++j) {
    Eigen::Vector3d uvq;
    const Eigen::Vector3d pc = to_camera * map.positions[j];
    if (!projectInverseDepth(f.camera, pc, uvq)) continue;
    const double u = uvq.x(), v = uvq.y();
    if (u < umin || u > umax || v < vmin || v > vmax) continue;
    if (visible) (*visible)[j] = true;
    // Without a pyramid every keypoint is full resolution: scale 1, the plain radius.
    const double expected =
        scaled ? predictedScale(map.reference_distances[j], pc.norm(), f.max_scale) : 1.0;
    const double radius =
        o.radius * expected + (o.spread ? o.spread_scale * (*o.spread)[j] : 0.0);
    const double r2 = radius * radius;
    const double min_scale = o.scale_tolerance > 0 ? expected / o.scale_tolerance : 0.0;
    const double max_scale = o.scale_tolerance > 0 ? expected * o.scale_tolerance : 1e300;
    const int c0 = std::max(0, static_cast<int>((u - radius) / cell_));
    const int c1 = std::min(cols_ - 1, static_cast<int>((u + radius) / cell_));
    const int r0 = std::max(0, static_cast<int>((v - radius) / cell_));
    const int r1 = std::min(rows_ - 1, static_cast<int>((v + radius) / cell_));
    int best = -1, best_d = o.max_hamming + 1, second_d = 1 << 20;
    const uint8_t* dj = map.descriptor(j);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const int cell = r * cols_ + c;
        for (int k = start_[cell]; k < start_[cell + 1]; ++k) {
          const int i = order_[k];
          const Eigen::Vector2d& px = f.pixels[i];
          if ((px.x() - u) * (px.x() - u) + (px.y() - v) * (px.y() - v) > r2) continue;
          if (scaled && (f.scales[i] < min_scale || f.scales[i] > max_scale)) continue;
          const int d = hammingDistance(f.descriptor(i), dj, bytes);
          if (d < best_d) {
            second_d = best_d;
            best_d = d;
            best = i;
          } else if (d < second_d) {
            second_d = d;
          }
        }
      }
    }
    if (best < 0 || best_d > o.max_hamming) continue;
    if (o.ratio < 1.0 && second_d <= o.max_hamming && best_d >= o.ratio * second_d) continue;
    if (best_d < best_distance_[best]) {
      best_distance_[best] = best_d;
      best_landmark_[best] = static_cast<int>(j);
    }
  }
  for (size_t i = 0; i < f.size(); ++i)
    if (best_landmark_[i] >= 0)
      matches.push_back({static_cast<int>(i), best_landmark_[i], best_distance_[i]});
}

}  // namespace abi_v1
}  // namespace plugslam
