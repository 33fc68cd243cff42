#include "stereo_preprocessor.h"

#include <chrono>
#include <opencv2/imgproc.hpp>

#include "plugslam/errors.h"

namespace plugslam {
namespace visual {

namespace {
double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

StereoPreprocessor::StereoPreprocessor() = default;
StereoPreprocessor::~StereoPreprocessor() = default;

void StereoPreprocessor::configure() { KeypointPreprocessor::configure(); }

bool StereoPreprocessor::process(Frame& frame) {
  const Image* l = frame.raw.find<Image>(left());
  const Image* r = frame.raw.find<Image>(right());
  const CameraInfo* cam = frame.raw.find<CameraInfo>(camera());
  if (!l || !r) return false;
  if (!cam)
    throw InputError("stereo: raw entry '" + camera() + "' (CameraInfo) is missing: the pair "
                     "cannot be triangulated without a calibration");
  if (!(cam->baseline > 0) || !(cam->fx > 0) || !(cam->fy > 0))
    throw InputError("stereo: calibration '" + camera() + "' needs fx, fy > 0 and a baseline > 0");
  if (l->width != r->width || l->height != r->height)
    throw InputError("stereo: the left image is " + std::to_string(l->width) + "x" +
                     std::to_string(l->height) + " but the right one " +
                     std::to_string(r->width) + "x" + std::to_string(r->height));
  configure();  // cheap; picks up parameters changed at run time
  const cv::Mat gl = greyOf(*l), gr = greyOf(*r);
  auto t0 = std::chrono::steady_clock::now();
  extractor_.extract(gl, kl_, dl_);
  extractor_.extract(gr, kr_, dr_);
  extraction_s_ += secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  StereoMatchOptions mo;
  mo.min_disparity = min_disparity();
  mo.max_disparity = std::min<double>(l->width, cam->fx * cam->baseline / min_depth());
  mo.row_tolerance = row_tolerance();
  mo.max_hamming = max_hamming();
  StereoMatcher::match(gl, gr, kl_, dl_, kr_, dr_, mo, disparity_);

  FeatureSet& f = frame.measurement.emplace<FeatureSet>(output());
  f.camera.fx = cam->fx;
  f.camera.fy = cam->fy;
  f.camera.cx = cam->cx;
  f.camera.cy = cam->cy;
  f.camera.baseline = cam->baseline;
  f.width = l->width;
  f.height = l->height;
  f.mount = cam->mount;
  f.stamp = l->stamp;
  f.descriptor_bytes = dl_.cols > 0 ? dl_.cols : 32;
  f.reserve(kl_.size());
  for (size_t i = 0; i < kl_.size(); ++i) {
    const uint32_t colour = colourAt(*l, cvRound(kl_[i].pt.x), cvRound(kl_[i].pt.y));
    f.pushStereo(Eigen::Vector2d(kl_[i].pt.x, kl_[i].pt.y), pixel_sigma(), disparity_[i],
                 disparity_sigma(), dl_.ptr<uint8_t>(static_cast<int>(i)), colour);
  }
  matching_s_ += secondsSince(t0);
  return true;
}

}  // namespace visual
}  // namespace plugslam
