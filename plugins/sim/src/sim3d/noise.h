#pragma once
// Sensor noise for rendered frames: Kinect-like depth noise and image noise with per-frame
// exposure gain. Every draw comes from (seed, frame, stream), so frame k is the same whatever
// order frames are produced in.
#include <cstdint>

#include "plugslam/sensor_data.h"
#include "sim3d/renderer.h"

namespace plugslam {
namespace sim {
namespace sim3d {

/// Kinect-like depth errors.
struct DepthNoise {
  bool enabled = true;                ///< false: depth is exact
  double sigma_a = 0.0012;            ///< sigma(z) = sigma_a + sigma_b * (z - z0)^2 [m]
  double sigma_b = 0.0019;            ///< [1/m]
  double z0 = 0.4;                    ///< [m]
  bool quantize = true;               ///< round to the structured-light disparity steps
  double disparity_baseline = 0.075;  ///< emitter-camera baseline for quantisation [m]
  double disparity_focal = 580.0;     ///< focal length for quantisation [px]
  double subpixel = 8.0;              ///< disparity steps per pixel
  double min_range = 0.4;             ///< closer: no reading [m]
  double max_range = 6.0;             ///< farther: no reading [m]
  double grazing_deg = 78.0;          ///< incidence beyond this from the normal: no reading [deg]
  double dropout = 0.002;             ///< probability of a missing pixel
  /// Throws InputError naming the field when a value is out of range.
  void validate() const;
};

/// Image noise and exposure.
struct ImageNoise {
  bool enabled = true;       ///< false: the shaded image is kept exactly
  double sigma = 2.0;        ///< gaussian noise per channel [grey levels]
  double gain_sigma = 0.15;  ///< exposure: log-gain varies smoothly with this amplitude
  double gain_period = 4.0;  ///< typical period of exposure changes [frames / rate, s]
  /// Throws InputError naming the field when a value is out of range.
  void validate() const;
};

/// The exposure gain at time `stamp` (smooth in time, 1 when gain_sigma is 0).
double exposureGain(const ImageNoise& noise, uint64_t seed, double stamp);

/// Converts the render's depth to a DepthImage, applying `noise` (draws from seed, frame).
void makeDepthImage(const RenderBuffers& buffers, const DepthNoise& noise, uint64_t seed,
                    uint64_t frame, DepthImage* depth);

/// Applies exposure gain and gaussian noise to `image` in place (draws from seed, frame, stream).
void applyImageNoise(const ImageNoise& noise, uint64_t seed, uint64_t frame, uint64_t stream,
                     double gain, Image* image);

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
