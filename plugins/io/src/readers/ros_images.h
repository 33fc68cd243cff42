#pragma once
// ROS camera messages (sensor_msgs Image, CompressedImage, CameraInfo, as decoded by
// cdr_messages.h) to the SDK's raw camera types: the pixel encodings the camera plugins take,
// depth in metres, and the pinhole + distortion of a CameraInfo. Compressed images are decoded by
// the camera dataset sources' own decoders (images/image_file.h: libpng, libjpeg-turbo).
#include <string>

#include "plugslam/sensor_data.h"
#include "readers/cdr_messages.h"

namespace plugslam {
namespace io {

/// An Image message (mono8, mono16, rgb8, bgr8, rgba8, bgra8; 8UC1, 8UC3 as mono8, bgr8) as an
/// 8-bit grey or RGB Image (16 bits keep their high byte, alpha is dropped). ParseError("", 0,
/// why) for another encoding (depth encodings name the `depth` parameter) or data that does not
/// match width, height and step.
Image imageFromRos(const ImageMsg& msg);
/// A CompressedImage message (a PNG or JPEG, whatever its `format` says) decoded as stored:
/// grey stays grey, colour becomes RGB. ParseError when the bytes are not a whole image.
Image imageFromRos(const CompressedImageMsg& msg);
/// A depth Image message in metres, 0 = no reading: 16UC1 (and mono16) in millimetres (0 and
/// 65535 are no reading, as in the depth PNGs), 32FC1 in metres (NaN, inf and <= 0 are no
/// reading), as REP 118 defines them. ParseError for another encoding or a size mismatch.
DepthImage depthFromRos(const ImageMsg& msg);

/// True when the CameraInfo says its image needs no rectification: no distortion (every
/// coefficient zero), R the identity and P's left 3x3 equal to K.
bool isRectifiedCamera(const CameraInfoMsg& msg);
/// The camera's pinhole, size and distortion: K and D (raw images), or, `rectified`, P's
/// pinhole and no distortion (images of the rectified topic). ParseError for an unknown
/// distortion model, a coefficient count that does not fit it, or a non-positive focal length.
CameraIntrinsics intrinsicsFromRos(const CameraInfoMsg& msg, bool rectified);

}  // namespace io
}  // namespace plugslam
