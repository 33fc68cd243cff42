// laser2d_bench LOG [association=kdtree|projective] [odom=1|0] [repeat=N] [map_dir=DIR]
// [module.param=value]...
// Front-end speed and local accuracy (RPE over 1 m against the log's poses) on a CARMEN log;
// module is preprocessor, slice, map, aligner or splitter.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

#include "intel_run.h"

namespace {
void usage(std::FILE* to, const char* argv0) {
  std::fprintf(to,
               "usage: %s LOG [association=kdtree|projective] [odom=1|0] [repeat=N] "
               "[map_dir=DIR] [module.param=v]...\n"
               "Front-end speed and local accuracy (RPE over 1 m against the log's poses) on a "
               "CARMEN log;\nmodule is preprocessor, slice, map, aligner or splitter.\n",
               argv0);
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    usage(stderr, argv[0]);
    return 2;
  }
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      usage(stdout, argv[0]);
      return 0;
    }
    if (i > 1 || arg.rfind("-", 0) != 0) continue;
    std::fprintf(stderr, "laser2d_bench: unknown option %s\n", arg.c_str());  // not a log path
    usage(stderr, argv[0]);
    return 2;
  }
  try {
    plugslam::laser2d::test::FrontendOptions options;
    for (int i = 2; i < argc; ++i) {
      const std::string arg = argv[i];
      const auto eq = arg.find('=');
      if (eq == std::string::npos) throw std::runtime_error("expected key=value, got " + arg);
      const std::string key = arg.substr(0, eq), value = arg.substr(eq + 1);
      if (key == "association")
        options.association = value;
      else if (key == "odom")
        options.odometry = value != "0";
      else if (key == "map_dir")
        options.map_dir = value;
      else if (key == "repeat")
        options.repeat = std::atoi(value.c_str());
      else
        options.overrides.emplace_back(key, value);
    }
    const auto run = plugslam::laser2d::test::runFrontend(argv[1], options);
    const auto rpe = plugslam::laser2d::test::relativeError(run, 1.0);
    std::printf(
        "scans %zu (%zu beams), association %s, %s\n"
        "front-end %.3f s, %.0f scans/s (single thread, best of %d)\n"
        "aligned %zu, local maps %zu, mean inlier ratio %.3f\n"
        "RPE over 1 m (%zu pairs): translation mean %.4f m rmse %.4f m, rotation mean %.3f deg "
        "rmse %.3f deg\n",
        run.scans, run.beams, options.association.c_str(),
        options.odometry ? "odometry prediction" : "constant velocity", run.seconds,
        run.scans_per_second, options.repeat, run.aligned, run.local_maps, run.mean_inlier_ratio,
        rpe.pairs, rpe.translation.mean, rpe.translation.rmse, rpe.rotation_deg.mean,
        rpe.rotation_deg.rmse);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "laser2d_bench: %s\n", e.what());
    return 1;
  }
}
