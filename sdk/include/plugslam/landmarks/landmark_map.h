#pragma once
// The generic landmark cue's scene entry: 3D landmarks in the local map's frame, each with its
// uncertainty, a run-unique track id, observation counters and the descriptor it was last seen
// with (what the reprojection slice associates against and an appearance index can search).
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {

class OutArchive;
class InArchive;

/// Landmarks of one local map, structure of arrays.
struct LandmarkMap {
  std::vector<Eigen::Vector3d> positions;    ///< in the local map's frame [m]
  std::vector<Eigen::Matrix3d> covariances;  ///< of the positions [m^2]
  std::vector<uint64_t> ids;                 ///< track ids, unique over the run
  std::vector<uint32_t> observations;        ///< frames that matched it (creation included)
  std::vector<uint32_t> visible;             ///< frames it projected into (creation included)
  std::vector<uint64_t> last_seen;           ///< seq of the last frame that matched it
  std::vector<uint32_t> colours;             ///< 0xRRGGBB of the last observation
  /// Distance [m] from which the landmark looks as large as a full-resolution keypoint: its
  /// last observation's distance times that keypoint's pyramid scale (0: unknown). Seen from d,
  /// it is expected at scale reference_distance / d.
  std::vector<double> reference_distances;
  int descriptor_bytes = 32;                 ///< bytes per descriptor
  std::vector<uint8_t> descriptors;          ///< size() * descriptor_bytes (last observation)
  /// Changes whenever the map is modified (process-wide unique, see touch()).
  uint64_t revision = 0;

  /// Number of landmarks.
  size_t size() const { return positions.size(); }
  /// True without landmarks.
  bool empty() const { return positions.empty(); }
  /// Descriptor of landmark i.
  const uint8_t* descriptor(size_t i) const {
    return descriptors.data() + i * static_cast<size_t>(descriptor_bytes);
  }
  /// Mutable descriptor of landmark i.
  uint8_t* descriptor(size_t i) {
    return descriptors.data() + i * static_cast<size_t>(descriptor_bytes);
  }
  /// Appends a landmark seen once, at frame `seq` (reference_distance: see reference_distances).
  void push(const Eigen::Vector3d& position, const Eigen::Matrix3d& covariance, uint64_t id,
            const uint8_t* descriptor, uint32_t colour, uint64_t seq,
            double reference_distance = 0.0);
  /// Keeps the landmarks whose flag is true, in order (keep.size() == size()).
  void keepOnly(const std::vector<bool>& keep);
  /// Removes every landmark.
  void clear();
  /// Marks the map as modified (a new unique revision).
  void touch();
  /// Throws InputError unless every array matches size().
  void checkConsistent() const;
};

/// Serializes a landmark map.
void save(OutArchive& ar, const LandmarkMap& map);
/// Deserializes a landmark map (ParseError when the arrays disagree in length).
void load(InArchive& ar, LandmarkMap& map);

}  // namespace abi_v1
}  // namespace plugslam
