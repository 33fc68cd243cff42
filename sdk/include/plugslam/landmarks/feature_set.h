#pragma once
// The generic landmark cue's measurement: the keypoints of one camera frame with binary
// descriptors and, where the sensor measured it, their depth. A stereo preprocessor fills it from
// a rectified pair (depth from disparity), an RGB-D one from a depth image; the cue's slices
// (reprojection aligner slice, landmark-map tracker slice) and writers need no OpenCV.
#include <Eigen/Geometry>
#include <cstdint>
#include <cstring>
#include <vector>

#include "plugslam/solver/projection_factors.h"

namespace plugslam {
inline namespace abi_v1 {

class OutArchive;
class InArchive;

/// Number of set bits of `x`. Where the compiler may not use the CPU's popcount instruction
/// (x86-64 without -mpopcnt, the distributions' baseline), __builtin_popcountll is a call into
/// libgcc per word: 2.5 % of a stereo run's instructions went to it, more than the inline count
/// below costs in all.
inline int popcount64(uint64_t x) {
#if defined(__POPCNT__) || !(defined(__x86_64__) || defined(__i386__))
  return __builtin_popcountll(x);
#else
  x -= (x >> 1) & 0x5555555555555555ULL;
  x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
  x = (x + (x >> 4)) & 0x0f0f0f0f0f0f0f0fULL;
  return static_cast<int>((x * 0x0101010101010101ULL) >> 56);
#endif
}

/// Hamming distance between two binary descriptors of `bytes` bytes (ORB: 32).
inline int hammingDistance(const uint8_t* a, const uint8_t* b, int bytes) {
  int d = 0;
  int i = 0;
  for (; i + 8 <= bytes; i += 8) {
    uint64_t x, y;
    std::memcpy(&x, a + i, 8);
    std::memcpy(&y, b + i, 8);
    d += popcount64(x ^ y);
  }
  for (; i < bytes; ++i) d += popcount64(static_cast<uint64_t>(a[i] ^ b[i]));
  return d;
}

/// Covariance of the camera-frame point seen at pixel (u, v) with inverse depth q = 1/z, from
/// independent pixel noise sigma_px (u and v) and inverse-depth noise sigma_q (first order).
Eigen::Matrix3d pointCovariance(const PinholeCamera& camera, const Eigen::Vector2d& uv, double q,
                                double sigma_px, double sigma_q);

/// Keypoints of one camera frame (measurement entry of the landmark cue), structure of arrays.
/// Pixels are in an ideal pinhole (`camera`: rectified / undistorted); the point of a feature
/// with depth is in the camera's optical frame (x right, y down, z forward).
struct FeatureSet {
  /// The pinhole the pixels are expressed in (baseline: the stereo baseline, 0 otherwise).
  PinholeCamera camera;
  int width = 0;   ///< image width [px]
  int height = 0;  ///< image height [px]
  /// Camera pose in the robot frame: the slices align the robot, so a camera can share one pose
  /// with other cues (a laser in a 2D pipeline).
  Eigen::Isometry3d mount = Eigen::Isometry3d::Identity();
  double stamp = 0;  ///< image time [s]

  std::vector<Eigen::Vector2d> pixels;  ///< (u, v) of each keypoint [px]
  std::vector<double> pixel_sigma;      ///< std. dev. of u and of v [px] (grows with the level)
  /// Pyramid scale of the level each keypoint was found at (1: full resolution; s: the image
  /// shrunk s times, where the keypoint's patch covers s times as many full-resolution pixels).
  std::vector<double> scales;
  /// Scale of the coarsest pyramid level the keypoints were searched at (1: no pyramid).
  double max_scale = 1.0;
  /// Inverse depth 1/z [1/m]; 0 = no depth (the feature still constrains bearing).
  std::vector<double> inverse_depth;
  std::vector<double> inverse_depth_sigma;   ///< std. dev. of the inverse depth [1/m]
  std::vector<Eigen::Vector3d> points;       ///< camera-frame point [m] (zero without depth)
  std::vector<Eigen::Matrix3d> covariances;  ///< covariance of `points` [m^2] (zero without)
  int descriptor_bytes = 32;                 ///< bytes per descriptor
  std::vector<uint8_t> descriptors;          ///< size() * descriptor_bytes, row by row
  std::vector<uint32_t> colours;             ///< 0xRRGGBB per keypoint

  /// Number of keypoints.
  size_t size() const { return pixels.size(); }
  /// True without keypoints.
  bool empty() const { return pixels.empty(); }
  /// Removes every keypoint (keeps camera, size and mount).
  void clear();
  /// Reserves room for n keypoints.
  void reserve(size_t n);
  /// True when keypoint i has a depth.
  bool hasDepth(size_t i) const { return inverse_depth[i] > 0; }
  /// Descriptor of keypoint i (descriptor_bytes bytes).
  const uint8_t* descriptor(size_t i) const {
    return descriptors.data() + i * static_cast<size_t>(descriptor_bytes);
  }
  /// Appends a keypoint with depth z [m] and depth noise sigma_z [m] (RGB-D); z <= 0: no depth.
  /// `scale` is its pyramid level's scale (sigma_px is the noise at that level, in full-resolution
  /// pixels).
  void pushDepth(const Eigen::Vector2d& uv, double sigma_px, double z, double sigma_z,
                 const uint8_t* descriptor, uint32_t colour, double scale = 1.0);
  /// Appends a keypoint matched in the right image of a rectified pair at disparity d = uL - uR
  /// [px] with noise sigma_d [px]; needs camera.baseline > 0. d <= 0: no depth. `scale` as in
  /// pushDepth.
  void pushStereo(const Eigen::Vector2d& uv, double sigma_px, double disparity, double sigma_d,
                  const uint8_t* descriptor, uint32_t colour, double scale = 1.0);
  /// Throws InputError unless every array matches size() (descriptors: size() x bytes).
  void checkConsistent() const;
};

/// Serializes a feature set.
void save(OutArchive& ar, const FeatureSet& features);
/// Deserializes a feature set (ParseError when the arrays disagree in length).
void load(InArchive& ar, FeatureSet& features);
/// Serializes pinhole intrinsics.
void save(OutArchive& ar, const PinholeCamera& camera);
/// Deserializes pinhole intrinsics.
void load(InArchive& ar, PinholeCamera& camera);

}  // namespace abi_v1
}  // namespace plugslam
