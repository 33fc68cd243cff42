// How well an RGB-D dataset's reference poses explain its own depth images, and what the depth
// alone says the frame-to-frame motion is (depth_check.h). The frames are the config's source,
// so the camera, depth units, registration and the ground truth's frame are exactly those a
// run sees. With --estimate, a trajectory's frame-to-frame motion is scored against both; with
// --planes, every pair is also registered by its planes alone (plane_registration.h, no
// reference), and the best hypothesis is compared with the depth's motion.
//   rgbd_depth_check CONFIG [--set path=value]... [--max-gap K] [--estimate TRAJ.tum]
//                    [--planes] [--depth ENTRY] [--camera ENTRY] [--ground-truth ENTRY]
// Prints one JSON object (scripts/bench/visual.sh reads it).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "config_builder.h"
#include "depth_check.h"
#include "plane_registration.h"
#include "plugin_manager.h"
#include "plugslam/trajectory.h"
#include "run_config.h"
#include "spdlog/sinks/stdout_color_sinks.h"
#include "spdlog/spdlog.h"

namespace {

using plugslam::SE3;
using namespace plugslam::rgbd;

constexpr const char* kUsage =
    "usage: rgbd_depth_check CONFIG [--set path=value]... [--max-gap K] [--estimate TRAJ.tum]\n"
    "                        [--planes] [--depth ENTRY] [--camera ENTRY] [--ground-truth ENTRY]\n"
    "Aligns the depth images of every pair of frames at most K apart (default 1), starting at\n"
    "the source's ground truth, and prints how far the depth moves the reference (JSON).\n"
    "--estimate scores a trajectory's frame-to-frame motion against the depth's.\n"
    "--planes also registers each pair by its planes alone, with no reference, and reports the\n"
    "best hypothesis against the depth's motion (planes_off_mm, planes_off_deg).\n";

double mm(const SE3& x) { return x.translation().norm() * 1000.0; }
double deg(const SE3& x) { return Eigen::AngleAxisd(x.linear()).angle() * 180.0 / M_PI; }

std::string poseJson(const SE3& x) {
  const Eigen::Quaterniond q(x.linear());
  char buf[256];
  std::snprintf(buf, sizeof buf, "[%.6f, %.6f, %.6f, %.8f, %.8f, %.8f, %.8f]", x.translation().x(),
                x.translation().y(), x.translation().z(), q.x(), q.y(), q.z(), q.w());
  return buf;
}

const char* sep(const std::string& s) { return s.empty() ? "" : ",\n    "; }

}  // namespace

int main(int argc, char** argv) {
  std::string config, estimate_path, depth_entry = "depth", camera_entry = "camera",
                                     gt_entry = "ground_truth";
  std::vector<std::string> sets;
  int max_gap = 1;
  bool planes = false;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    const auto value = [&]() -> std::string {
      if (a + 1 >= argc) {
        std::fprintf(stderr, "rgbd_depth_check: %s needs a value\n%s", arg.c_str(), kUsage);
        std::exit(2);
      }
      return argv[++a];
    };
    if (arg == "-h" || arg == "--help") {
      std::fputs(kUsage, stdout);
      return 0;
    } else if (arg == "--set") {
      sets.push_back(value());
    } else if (arg == "--max-gap") {
      max_gap = std::atoi(value().c_str());
    } else if (arg == "--estimate") {
      estimate_path = value();
    } else if (arg == "--planes") {
      planes = true;
    } else if (arg == "--depth") {
      depth_entry = value();
    } else if (arg == "--camera") {
      camera_entry = value();
    } else if (arg == "--ground-truth") {
      gt_entry = value();
    } else if (config.empty() && arg.rfind("-", 0) != 0) {
      config = arg;
    } else {
      std::fprintf(stderr, "rgbd_depth_check: unexpected argument '%s'\n%s", arg.c_str(), kUsage);
      return 2;
    }
  }
  if (config.empty() || max_gap < 1) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  // Standard output is the JSON: the sources' messages go to standard error.
  spdlog::set_default_logger(spdlog::stderr_color_mt("rgbd_depth_check"));
  try {
    plugslam::runtime::ConfigDocument doc = plugslam::runtime::loadConfigFile(config);
    for (const auto& s : sets) plugslam::runtime::applyOverride(doc, s);
    plugslam::runtime::PluginManager plugins;
    auto run = plugslam::runtime::buildRun(doc, plugins);
    const std::vector<DepthCheckFrame> frames =
        readDepthCheckFrames(*run->source, depth_entry, camera_entry, gt_entry);
    const DepthCheck check = checkDepth(frames, max_gap);

    std::vector<std::vector<DepthPlane>> frame_planes;
    if (planes)
      for (const DepthCheckFrame& f : frames)
        frame_planes.push_back(extractPlanes(f.surface, DepthNoiseModel{}));
    std::string pairs;
    for (const DepthCheckPair& p : check.pairs) {
      std::string by_planes;
      if (planes) {
        const size_t i = static_cast<size_t>(p.i), j = static_cast<size_t>(p.j);
        const std::vector<PlaneHypothesis> h =
            registerPlanes(frames[i].surface, frame_planes[i], frames[j].surface,
                           frame_planes[j], DepthNoiseModel{});
        char pb[320];
        if (h.empty()) {
          std::snprintf(pb, sizeof pb, ", \"planes\": [%zu, %zu], \"plane_hypotheses\": 0",
                        frame_planes[i].size(), frame_planes[j].size());
        } else {
          const SE3 off = p.alignment.pose.inverse() * h.front().pose;
          std::snprintf(pb, sizeof pb,
                        ", \"planes\": [%zu, %zu], \"plane_hypotheses\": %zu, "
                        "\"planes_share\": %.3f, \"planes_off_mm\": %.1f, "
                        "\"planes_off_deg\": %.2f",
                        frame_planes[i].size(), frame_planes[j].size(), h.size(),
                        h.front().agreement.share(), mm(off), deg(off));
        }
        by_planes = pb;
      }
      char buf[900];
      std::snprintf(buf, sizeof buf,
                    "%s{\"i\": %d, \"j\": %d, \"shares_surface\": %s, \"overlap\": %.3f, "
                    "\"rms_reference_mm\": %.3f, \"rms_depth_mm\": %.3f, "
                    "\"reference_off_mm\": %.2f, \"reference_off_deg\": %.3f, "
                    "\"conditioning\": %.2e, \"depth_relative\": %s%s}",
                    sep(pairs), p.i, p.j, p.shares_surface ? "true" : "false", p.overlap,
                    p.alignment.rms_initial * 1000, p.alignment.rms * 1000,
                    p.shares_surface ? mm(p.reference_off) : 0.0,
                    p.shares_surface ? deg(p.reference_off) : 0.0, p.alignment.conditioning,
                    poseJson(p.alignment.pose).c_str(), by_planes.c_str());
      pairs += buf;
    }

    std::optional<plugslam::Trajectory> estimate;
    if (!estimate_path.empty()) estimate = plugslam::readTumTrajectory(estimate_path);
    const auto estimated = [&](int i) -> std::optional<SE3> {
      if (!estimate) return std::nullopt;
      auto k = estimate->nearest(frames[static_cast<size_t>(i)].stamp, 1e-6);
      if (!k) return std::nullopt;
      return (*estimate)[*k].pose;
    };
    std::string steps;
    double worst_mm = 0, worst_deg = 0, worst_ref_mm = 0, worst_ref_deg = 0;
    int measured = 0, unmeasured = 0;
    for (const DepthCheckStep& s : check.steps) {
      char buf[640];
      if (!s.depth) {
        ++unmeasured;
        std::snprintf(buf, sizeof buf, "%s{\"i\": %d, \"j\": %d, \"measured\": false}",
                      sep(steps), s.i, s.j);
        steps += buf;
        continue;
      }
      ++measured;
      const SE3 ref_off = s.reference.inverse() * *s.depth;
      worst_ref_mm = std::max(worst_ref_mm, mm(ref_off));
      worst_ref_deg = std::max(worst_ref_deg, deg(ref_off));
      std::string est;
      const auto ei = estimated(s.i), ej = estimated(s.j);
      if (ei && ej) {
        const SE3 e = ei->inverse() * *ej;
        const SE3 vs_depth = s.depth->inverse() * e, vs_ref = s.reference.inverse() * e;
        worst_mm = std::max(worst_mm, mm(vs_depth));
        worst_deg = std::max(worst_deg, deg(vs_depth));
        char eb[256];
        std::snprintf(eb, sizeof eb,
                      ", \"estimate_vs_depth_mm\": %.2f, \"estimate_vs_depth_deg\": %.3f, "
                      "\"estimate_vs_reference_mm\": %.2f, \"estimate_vs_reference_deg\": %.3f",
                      mm(vs_depth), deg(vs_depth), mm(vs_ref), deg(vs_ref));
        est = eb;
      }
      std::snprintf(buf, sizeof buf,
                    "%s{\"i\": %d, \"j\": %d, \"measured\": true, \"via\": %d, "
                    "\"reference_off_mm\": %.2f, \"reference_off_deg\": %.3f%s}",
                    sep(steps), s.i, s.j, s.via, mm(ref_off), deg(ref_off), est.c_str());
      steps += buf;
    }

    std::printf("{\n  \"frames\": %zu, \"max_gap\": %d, \"min_overlap\": %.2f,\n", frames.size(),
                max_gap, kMinDepthOverlap);
    std::printf("  \"pairs\": [\n    %s],\n", pairs.c_str());
    std::printf("  \"cycles\": {\"count\": %d, \"max_mm\": %.2f, \"max_deg\": %.4f},\n",
                check.cycles, check.cycle_max_m * 1000, check.cycle_max_rad * 180.0 / M_PI);
    std::printf("  \"steps\": [\n    %s],\n", steps.c_str());
    std::printf("  \"summary\": {\"steps_measured\": %d, \"steps_unmeasured\": %d, "
                "\"reference_off_max_mm\": %.2f, \"reference_off_max_deg\": %.3f",
                measured, unmeasured, worst_ref_mm, worst_ref_deg);
    if (estimate)
      std::printf(", \"estimate_vs_depth_max_mm\": %.2f, \"estimate_vs_depth_max_deg\": %.3f",
                  worst_mm, worst_deg);
    std::printf("}\n}\n");
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rgbd_depth_check: %s\n", e.what());
    return 1;
  }
}
