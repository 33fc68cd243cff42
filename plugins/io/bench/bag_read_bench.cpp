// Reading speed of the bag sources (issue 21's target: >= 50 MB/s of bag): each bag is read to
// its end through the source a run uses (storage, decompression, CRCs, CDR or ROS 1 decoding,
// synchronisation into frames), timed; MB/s = the bag's bytes on disk / wall time. The median of
// REPEATS passes. scripts/bench/ros2.sh runs it and writes the table.
//   io_bag_read_bench REPEATS BAG...      (.bag = io.RosbagSource, else io.Ros2BagSource)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "plugslam/errors.h"
#include "sources/ros2_bag_source.h"
#include "sources/rosbag_source.h"

namespace {

uint64_t bytesOf(const std::string& path) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(path)) return fs::file_size(path);
  uint64_t n = 0;
  for (const auto& e : fs::directory_iterator(path)) {
    if (e.path().extension() == ".mcap" || e.path().extension() == ".db3") n += e.file_size();
  }
  return n;
}

template <typename Source>
std::pair<double, size_t> pass(const std::string& path) {
  const auto t0 = std::chrono::steady_clock::now();
  Source s;
  s.path = path;
  s.mounts = std::vector<double>{0.07, 0.0, 0.0};
  s.configure();
  plugslam::Frame f;
  size_t frames = 0;
  while (s.next(f)) ++frames;
  const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return {dt, frames};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: io_bag_read_bench REPEATS BAG...\n");
    return 2;
  }
  const int repeats = std::max(1, std::atoi(argv[1]));
  try {
    std::printf("bag\tbytes\tframes\tseconds\tMB_per_s\n");
    for (int i = 2; i < argc; ++i) {
      const std::string path = argv[i];
      const bool ros1 = path.size() > 4 && path.compare(path.size() - 4, 4, ".bag") == 0;
      std::vector<double> times;
      size_t frames = 0;
      for (int r = 0; r < repeats; ++r) {
        auto [dt, n] = ros1 ? pass<plugslam::io::RosbagSource>(path)
                            : pass<plugslam::io::Ros2BagSource>(path);
        times.push_back(dt);
        frames = n;
      }
      std::sort(times.begin(), times.end());
      const double median = times[times.size() / 2];
      const uint64_t bytes = bytesOf(path);
      std::printf("%s\t%llu\t%zu\t%.4f\t%.1f\n", path.c_str(),
                  static_cast<unsigned long long>(bytes), frames, median, bytes / median / 1e6);
    }
  } catch (const plugslam::Error& e) {
    std::fprintf(stderr, "io_bag_read_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
