#pragma once
// The depth of a keypoint from a depth image: a noise model for structured-light depth and the
// checks that keep a keypoint's depth only where the surface under it is continuous.
#include "plugslam/configurable.h"
#include "plugslam/param.h"
#include "plugslam/sensor_data.h"

namespace plugslam {
namespace rgbd {

/// Axial noise of a depth camera: sigma(z) = a + b (z - z0)^2. The defaults are Nguyen, Izadi and
/// Lovell's fit for the Kinect v1 ("Modeling Kinect Sensor Noise for Improved 3D Reconstruction
/// and Tracking", 3DIMPVT 2012, eq. 5: 1.2 mm + 1.9 mm/m^2 (z - 0.4 m)^2, surfaces within 60
/// degrees of head-on), the noise of every structured-light sensor that ranges by disparity.
struct DepthNoiseModel {
  double a = 0.0012;  ///< noise at z0 [m]
  double b = 0.0019;  ///< growth with the squared distance from z0 [1/m]
  double z0 = 0.4;    ///< distance of the least noise [m]
  /// Standard deviation of a depth reading at z [m].
  double sigma(double z) const { return a + b * (z - z0) * (z - z0); }
};

/// The noise model as a module's parameters `depth_sigma_a`, `_b` and `_z0` (Kinect v1 by
/// default): the preprocessor and the dense depth cue read the same sensor, and say it alike.
struct DepthNoiseParams {
  /// Declares the three parameters on `owner`.
  explicit DepthNoiseParams(Configurable* owner);
  Param<double> a;   ///< `depth_sigma_a` [m]
  Param<double> b;   ///< `depth_sigma_b` [1/m]
  Param<double> z0;  ///< `depth_sigma_z0` [m]
  /// The model the parameters state.
  DepthNoiseModel model() const;
};

/// How a keypoint's depth is read.
struct DepthSampling {
  DepthNoiseModel noise;  ///< the sensor's axial noise
  /// tan of the largest incidence angle a sensor ranges at: a neighbour's depth may differ by
  /// z tan(angle) / f per pixel of distance on a slanted surface; more is an occlusion edge.
  double tan_max_incidence = 5.67;  // tan(80 deg)
  double focal = 500;               ///< focal length of the depth image's pixels [px]
  double pixel_sigma = 1.0;         ///< the keypoint position's noise [px]
};

/// A keypoint's depth: z = 0 when it has none.
struct DepthSample {
  double z = 0;      ///< depth [m]
  double sigma = 0;  ///< its standard deviation [m]
};

/// The depth at pixel (x, y), with the noise of the reading and of the keypoint's position on a
/// slanted surface (the depth gradient times the pixel noise). None on the image border, where
/// the pixel or a neighbour has no reading (structured light's shadows lie along occlusion
/// edges), or where a neighbour's depth differs more than a continuous surface allows (the
/// keypoint sits on an occlusion edge: foreground and background are both within a pixel).
DepthSample sampleDepth(const DepthImage& depth, int x, int y, const DepthSampling& sampling);

}  // namespace rgbd
}  // namespace plugslam
