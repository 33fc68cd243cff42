#include "builtin_types.h"

#include "modules/graph/consistency_filter.h"
#include "modules/graph/odometry_audit.h"
#include "modules/graph/residual_veto.h"
#include "plugslam/alignment_validator.h"
#include "plugslam/graph_slam.h"
#include "plugslam/graph_writer.h"
#include "plugslam/landmarks/appearance_detector.h"
#include "plugslam/landmarks/appearance_validator.h"
#include "plugslam/landmarks/landmark_map_writer.h"
#include "plugslam/landmarks/landmark_slices.h"
#include "plugslam/localizer.h"
#include "plugslam/loop_closure.h"
#include "plugslam/multi_tracker.h"
#include "plugslam/pipeline.h"
#include "plugslam/proximity_detector.h"
#include "plugslam/view/drawers.h"

namespace plugslam {
inline namespace abi_v1 {
void registerBuiltinTypes(Registrar& registrar) {
  // Viewers show the landmark cue's map points (/map/landmarks), in the colour last seen.
  view::Drawers::instance().add<LandmarkMap>(
      registrar.plugin(), [](const LandmarkMap& map, view::PointCloud& out) {
        out.points.reserve(map.size());
        for (const auto& p : map.positions) out.points.push_back(p.cast<float>());
        if (map.colours.size() != map.size()) return;
        out.colors.reserve(map.size());
        for (uint32_t c : map.colours)
          out.colors.push_back({static_cast<uint8_t>(c >> 16), static_cast<uint8_t>(c >> 8),
                                static_cast<uint8_t>(c), 255});
      });
  registrar.add<Pipeline>("Pipeline", "the processing chain: preprocessors, tracker, graph");
  registrar.addBothSpaces<MultiAligner>(
      "MultiAligner", "one least-squares solve on an SE2 pose, one slice per cue",
      "one least-squares solve on an SE3 pose, one slice per cue");
  registrar.addBothSpaces<MultiTracker>("MultiTracker",
                                        "2D local map + slices: predict, align, merge, split",
                                        "3D local map + slices: predict, align, merge, split");
  registrar.addBothSpaces<Localizer>(
      "Localizer", "tracks in the frozen 2D maps of a saved session (run --localize)",
      "tracks in the frozen 3D maps of a saved session (run --localize)");
  registrar.addBothSpaces<GraphSlam>(
      "GraphSlam", "pose graph of 2D local maps, loop closing, global optimization",
      "pose graph of 3D local maps, loop closing, global optimization");
  registrar.add<ProximityDetector>("ProximityDetector",
                                   "loop candidates near in the current estimate, gated by drift");
  registrar.add<AppearanceDetector>(
      "AppearanceDetector",
      "loop candidates whose landmark descriptors match (online Hamming tree, no vocabulary)");
  registrar.add<AppearanceValidator>(
      "AppearanceValidator",
      "accepts a loop when the maps' landmarks register by descriptors and rigid RANSAC");
  registrar.addBothSpaces<AlignmentValidator>(
      "AlignmentValidator", "accepts a loop when the maps' scenes align with enough overlap");
  registrar.add<detail::ConsistencyFilter>(
      "ConsistencyFilter", "keeps the largest mutually consistent set of recently closed loops");
  registrar.add<detail::ResidualVeto>(
      "ResidualVeto", "after each optimization, rejects the loops the graph disagrees with most");
  registrar.add<detail::OdometryAudit>(
      "OdometryAudit",
      "when the run ends, rejects the loops that stretch an odometry edge beyond its bounds");
  registrar.add<GraphWriter>("GraphWriter", "writes the pose graph of local maps as g2o");
  registrar.addBothSpaces<ReprojectionSlice>(
      "ReprojectionSlice", "landmark cue: (u, v, 1/z) reprojection factors, planar robot pose",
      "landmark cue: (u, v, 1/z) reprojection factors");
  registrar.addBothSpaces<LandmarkMapSlice>(
      "LandmarkMapSlice", "landmark cue: merges keypoints into the local map's landmarks (2D)",
      "landmark cue: merges keypoints into the local map's landmarks");
  registrar.add<LandmarkMapWriter>(
      "LandmarkMapWriter", "landmark cue: the run's landmarks in the world as a binary PLY cloud");
  registrar.add<DistanceSplitter>("DistanceSplitter",
                                  "closes a local map on distance, angle, time or lost overlap");
}
}  // namespace abi_v1
}  // namespace plugslam
