// Trajectory readers (TUM, KITTI, g2o vertices, format detection). They read paths, so the input
// goes to a per-process file in /dev/shm (or the temp folder); the first byte picks the reader.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "fuzz_common.h"
#include "plugslam/errors.h"
#include "plugslam/trajectory.h"

namespace {

std::string scratch(const char* ext) {
  static const std::string dir = std::filesystem::is_directory("/dev/shm")
                                     ? "/dev/shm"
                                     : std::filesystem::temp_directory_path().string();
  return dir + "/plugslam-fuzz-" + std::to_string(getpid()) + ext;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* kExt[] = {".tum", ".kitti", ".g2o", ".txt"};
  const int which = data[0] % 4;
  const std::string path = scratch(kExt[which]);
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    switch (which) {
      case 0:
        plugslam::readTumTrajectory(path);
        break;
      case 1:
        // The same file as poses and as its own times file: exercises both parsers.
        plugslam::readKittiTrajectory(path, (data[0] & 4) ? path : "");
        break;
      case 2:
        plugslam::readG2oTrajectory(path);
        break;
      default:
        plugslam::readTrajectory(path, plugslam::TrajectoryFormat::Auto);
    }
  } catch (const plugslam::Error&) {
  }
  return 0;
}
