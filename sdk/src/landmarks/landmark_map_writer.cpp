#include "plugslam/landmarks/landmark_map_writer.h"

#include <cstring>
#include <ostream>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/landmarks/landmark_map.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
// PLY binary_little_endian stores floats as IEEE-754 little-endian bytes, whatever the host.
void putFloat(std::string& out, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits;
  std::memcpy(&bits, &f, 4);
  for (int k = 0; k < 4; ++k) out += static_cast<char>((bits >> (8 * k)) & 0xff);
}
}  // namespace

void writePly(const std::string& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<uint32_t>& colours) {
  if (colours.size() != points.size())
    throw InputError("writePly: " + std::to_string(points.size()) + " points but " +
                     std::to_string(colours.size()) + " colours");
  std::string body;
  body.reserve(points.size() * 15);
  for (size_t i = 0; i < points.size(); ++i) {
    putFloat(body, points[i].x());
    putFloat(body, points[i].y());
    putFloat(body, points[i].z());
    body += static_cast<char>((colours[i] >> 16) & 0xff);
    body += static_cast<char>((colours[i] >> 8) & 0xff);
    body += static_cast<char>(colours[i] & 0xff);
  }
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\ncomment plugslam landmark map\n"
        << "element vertex " << points.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
  });
}

void LandmarkMapWriter::end(const RunResult& result) {
  std::vector<Eigen::Vector3d> points;
  std::vector<uint32_t> colours;
  for (const auto& map : result.local_maps) {
    const LandmarkMap* lm = map->scene.find<LandmarkMap>(scene());
    if (!lm) continue;
    for (size_t j = 0; j < lm->size(); ++j) {
      if (lm->observations[j] < static_cast<uint32_t>(min_observations())) continue;
      points.push_back(map->origin * lm->positions[j]);
      colours.push_back(lm->colours[j]);
    }
  }
  writePly(out_dir_ + "/" + file(), points, colours);
}

}  // namespace abi_v1
}  // namespace plugslam
