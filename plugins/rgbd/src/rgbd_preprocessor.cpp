#include "rgbd_preprocessor.h"

#include <chrono>
#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace rgbd {
namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string size(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

}  // namespace

RgbdPreprocessor::RgbdPreprocessor() = default;
RgbdPreprocessor::~RgbdPreprocessor() = default;

void RgbdPreprocessor::configure() { KeypointPreprocessor::configure(); }

bool RgbdPreprocessor::process(Frame& frame) {
  const Image* colour = rgb.find(frame);
  const DepthImage* raw_depth = depth.find(frame);
  const CameraInfo* cam = camera.find(frame);
  if (!colour || !raw_depth) return false;
  if (!cam)
    throw InputError("rgbd: raw entry '" + camera.name() + "' (CameraInfo) is missing: keypoints "
                     "cannot be back-projected without a calibration");
  if (colour->width != cam->width || colour->height != cam->height)
    throw InputError("rgbd: the colour image is " + size(colour->width, colour->height) +
                     ", its calibration '" + camera.name() + "' says " +
                     size(cam->width, cam->height));
  configure();  // cheap; picks up parameters changed at run time
  registration_.prepare(*cam);
  if (registration_.identity() &&
      (raw_depth->width != colour->width || raw_depth->height != colour->height))
    throw InputError("rgbd: the depth image is " + size(raw_depth->width, raw_depth->height) +
                     " and the colour image " + size(colour->width, colour->height) +
                     ", but the calibration has no depth camera of its own to register with");

  auto t0 = std::chrono::steady_clock::now();
  extractor_.extract(visual::greyOf(*colour), keypoints_, descriptors_);
  extraction_s_ += secondsSince(t0);

  t0 = std::chrono::steady_clock::now();
  const DepthImage& d = registration_.apply(*raw_depth);
  DepthSampling sampling;
  sampling.noise = depth_sigma.model();
  sampling.tan_max_incidence = std::tan(max_incidence() * M_PI / 180.0);
  sampling.focal = std::min(cam->fx, cam->fy);  // registered depth is in the colour pixels
  // Keypoints are found in the raw colour image; the cue's pixels are its ideal pinhole's.
  xy_.resize(2 * keypoints_.size());
  for (size_t i = 0; i < keypoints_.size(); ++i) {
    xy_[2 * i] = keypoints_[i].pt.x;
    xy_[2 * i + 1] = keypoints_[i].pt.y;
  }
  undistortPixels(cam->intrinsics(), xy_);

  FeatureSet& f = output.emplace(frame);
  f.camera.fx = cam->fx;
  f.camera.fy = cam->fy;
  f.camera.cx = cam->cx;
  f.camera.cy = cam->cy;
  f.camera.baseline = 0;
  f.width = colour->width;
  f.height = colour->height;
  f.mount = cam->mount;
  f.stamp = colour->stamp;
  f.descriptor_bytes = descriptors_.cols > 0 ? descriptors_.cols : 32;
  f.max_scale = maxScale();
  f.reserve(keypoints_.size());
  for (size_t i = 0; i < keypoints_.size(); ++i) {
    const int x = cvRound(keypoints_[i].pt.x), y = cvRound(keypoints_[i].pt.y);
    // A keypoint found at pyramid scale s is located s times less precisely, in its pixel and
    // in the depth a slanted surface has under it.
    const double scale = keypointScale(keypoints_[i]);
    sampling.pixel_sigma = pixel_sigma() * scale;
    const DepthSample s = sampleDepth(d, x, y, sampling);
    f.pushDepth(Eigen::Vector2d(xy_[2 * i], xy_[2 * i + 1]), sampling.pixel_sigma, s.z, s.sigma,
                descriptors_.ptr<uint8_t>(static_cast<int>(i)), visual::colourAt(*colour, x, y),
                scale);
  }
  depth_s_ += secondsSince(t0);
  return true;
}

}  // namespace rgbd
}  // namespace plugslam
