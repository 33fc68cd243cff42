#include "depth_check.h"

#include <algorithm>
#include <map>
#include <utility>

#include "depth_registration.h"
#include "plugslam/errors.h"

namespace plugslam {
namespace rgbd {

namespace {
double angleOf(const SE3& x) { return Eigen::AngleAxisd(x.linear()).angle(); }
}  // namespace

std::vector<DepthCheckFrame> readDepthCheckFrames(Source& source, const std::string& depth,
                                                  const std::string& camera,
                                                  const std::string& ground_truth) {
  std::vector<DepthCheckFrame> frames;
  DepthRegistration registration;
  Frame frame;
  while (source.next(frame)) {
    const std::string at = "frame " + std::to_string(frames.size()) + ": ";
    const auto* d = frame.raw.find<DepthImage>(depth);
    const auto* c = frame.raw.find<CameraInfo>(camera);
    const auto* gt = frame.raw.find<Eigen::Isometry3d>(ground_truth);
    if (!d) throw InputError(at + "no depth image in raw entry '" + depth + "'");
    if (!c) throw InputError(at + "no calibration in raw entry '" + camera + "'");
    if (!gt) throw InputError(at + "no ground truth in raw entry '" + ground_truth + "'");
    registration.prepare(*c);
    CameraIntrinsics k = c->intrinsics();
    k.distortion = Distortion();  // registered depth is in the colour camera's ideal pinhole
    DepthCheckFrame f;
    f.stamp = frame.stamp;
    f.reference = *gt;
    f.surface = makeDepthSurface(registration.apply(*d), k);
    frames.push_back(std::move(f));
    frame = Frame();
  }
  return frames;
}

DepthCheck checkDepth(const std::vector<DepthCheckFrame>& frames, int max_gap,
                      const DepthAlignmentOptions& options) {
  DepthCheck out;
  const int n = static_cast<int>(frames.size());
  std::map<std::pair<int, int>, const DepthCheckPair*> shared;
  out.pairs.reserve(static_cast<size_t>(n) * static_cast<size_t>(std::max(1, max_gap)));
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n && j - i <= max_gap; ++j) {
      DepthCheckPair p;
      p.i = i;
      p.j = j;
      const SE3 ref = frames[static_cast<size_t>(i)].reference.inverse() *
                      frames[static_cast<size_t>(j)].reference;
      p.alignment = alignDepth(frames[static_cast<size_t>(i)].surface,
                               frames[static_cast<size_t>(j)].surface, ref, options);
      p.overlap = p.alignment.points > 0
                      ? static_cast<double>(p.alignment.pairs) / p.alignment.points
                      : 0.0;
      p.shares_surface = p.alignment.ok && p.overlap >= kMinDepthOverlap;
      p.reference_off = ref.inverse() * p.alignment.pose;
      out.pairs.push_back(std::move(p));
    }
  for (const DepthCheckPair& p : out.pairs)
    if (p.shares_surface) shared[{p.i, p.j}] = &p;

  for (const auto& [ij, a] : shared)
    for (const auto& [jk, b] : shared) {
      if (jk.first != ij.second) continue;
      auto ik = shared.find({ij.first, jk.second});
      if (ik == shared.end()) continue;
      const SE3 c = ik->second->alignment.pose.inverse() * a->alignment.pose * b->alignment.pose;
      out.cycle_max_m = std::max(out.cycle_max_m, c.translation().norm());
      out.cycle_max_rad = std::max(out.cycle_max_rad, angleOf(c));
      ++out.cycles;
    }

  // i <- j of a pair sharing surface, whichever way round it was aligned.
  const auto relative = [&](int i, int j) -> std::optional<SE3> {
    auto it = shared.find({std::min(i, j), std::max(i, j)});
    if (it == shared.end()) return std::nullopt;
    return i < j ? it->second->alignment.pose : it->second->alignment.pose.inverse();
  };
  const auto overlapOf = [&](int i, int j) {
    return shared.at({std::min(i, j), std::max(i, j)})->overlap;
  };
  for (int i = 0; i + 1 < n; ++i) {
    DepthCheckStep s;
    s.i = i;
    s.j = i + 1;
    s.reference = frames[static_cast<size_t>(i)].reference.inverse() *
                  frames[static_cast<size_t>(i + 1)].reference;
    s.depth = relative(i, i + 1);
    if (!s.depth) {
      double best = 0;
      for (int k = 0; k < n; ++k) {
        if (k == i || k == i + 1) continue;
        const auto ik = relative(i, k), kj = relative(k, i + 1);
        if (!ik || !kj) continue;
        const double o = std::min(overlapOf(i, k), overlapOf(k, i + 1));
        if (o <= best) continue;
        best = o;
        s.via = k;
        s.depth = *ik * *kj;
      }
    }
    out.steps.push_back(s);
  }
  return out;
}

}  // namespace rgbd
}  // namespace plugslam
