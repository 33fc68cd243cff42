#pragma once
// Camera images for the viewer: JPEG (libjpeg-turbo), shrunk to a viewer panel's size.
#include <string>

#include "plugslam/sensor_data.h"

namespace plugslam::runtime {

/// Widest image sent to viewers [px]: a viewer shows a camera in a panel of a screen, and a
/// smaller image costs a quarter of the bytes per halving.
constexpr int kViewImageMaxWidth = 640;

/// The whole factor an image `width` px wide is averaged down by for viewers (1 = as it is).
int viewShrinkFactor(int width);

/// A camera's calibration for its image as viewers get it (shrunk by viewShrinkFactor).
CameraInfo viewCalibration(const CameraInfo& info);

/// The image as viewers get it: averaged down by viewShrinkFactor while it is copied (a 2x
/// shrink reads each source pixel once), so a big camera image costs its pipeline a quarter-size
/// copy; an inconsistent image is copied as it is (encodeJpeg then says what is wrong).
Image viewImage(const Image& image);

/// The image as JPEG, averaged down by a whole factor until at most kViewImageMaxWidth wide;
/// 1 channel stays grey, 3 channels are RGB. Throws plugslam::Error on an inconsistent image.
std::string encodeJpeg(const Image& image, int quality = 80);

}  // namespace plugslam::runtime
