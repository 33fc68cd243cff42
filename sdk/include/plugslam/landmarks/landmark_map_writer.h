#pragma once
// The landmark map as an output ("sdk.LandmarkMapWriter"): every local map's landmarks moved into
// the world by the map's final (corrected) origin, as one binary little-endian PLY point cloud
// with the colour each landmark was last seen with.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <cstdint>

#include "plugslam/sink.h"

namespace plugslam {
inline namespace abi_v1 {

/// Writes the run's landmarks as PLY (x y z float, red green blue uchar) into the output folder.
class LandmarkMapWriter : public Sink {
 public:
  Param<std::string> file{this, "file", "landmarks.ply", "", "file name in the output folder"};
  Param<std::string> scene{this, "scene", "landmarks", "", "scene entry (LandmarkMap) to write"};
  Param<int> min_observations{this, "min_observations", 2, "",
                              "landmarks matched in fewer frames are left out (unconfirmed)",
                              Range{1, 1000000}};
  void begin(const std::string& out_dir) override { out_dir_ = out_dir; }
  void end(const RunResult& result) override;

 private:
  std::string out_dir_;
};

/// Writes points with colours (0xRRGGBB) as a binary little-endian PLY file, atomically.
void writePly(const std::string& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<uint32_t>& colours);

}  // namespace abi_v1
}  // namespace plugslam
