#include "stereo_preprocessor.h"

#include <chrono>
#include <opencv2/imgproc.hpp>

#include "plugslam/errors.h"

namespace plugslam {
namespace visual {

namespace {
constexpr int kRightOversampling = 3;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

StereoPreprocessor::StereoPreprocessor() = default;
StereoPreprocessor::~StereoPreprocessor() = default;

void StereoPreprocessor::configure() {
  // The front-end is single-threaded and deterministic (DESIGN.md, Threads): OpenCV runs its
  // functions sequentially in the caller instead of on its own pool (0 = no threading).
  if (cv::getNumThreads() != 1) cv::setNumThreads(0);
  KeypointPreprocessor::configure();
  OrbOptions o = orbOptions();
  // The disparity moves a left corner into another bucket of the right image, where stronger
  // corners may outrank it: the right image keeps more corners per bucket so that the left
  // keypoints' partners survive the bucketing.
  o.features *= kRightOversampling;
  right_extractor_.setOptions(o);
}

std::vector<Statistic> StereoPreprocessor::statistics() const {
  const double n = frames_ ? static_cast<double>(frames_) : 1.0;
  return {{"frames", static_cast<double>(frames_)},
          {"extraction_s", extraction_s_},
          {"matching_s", matching_s_},
          // The two parts of extraction, both images: FAST + bucketing, ORB descriptors.
          {"detection_s", extractor_.detectionSeconds() + right_extractor_.detectionSeconds()},
          {"description_s",
           extractor_.descriptionSeconds() + right_extractor_.descriptionSeconds()},
          {"keypoints_per_frame", static_cast<double>(keypoints_) / n},
          {"with_depth_per_frame", static_cast<double>(with_depth_) / n}};
}

bool StereoPreprocessor::process(Frame& frame) {
  const Image* l = left.find(frame);
  const Image* r = right.find(frame);
  const CameraInfo* cam = camera.find(frame);
  if (!l || !r) return false;
  if (!cam)
    throw InputError("stereo: raw entry '" + camera.name() + "' (CameraInfo) is missing: the pair "
                     "cannot be triangulated without a calibration");
  if (l->width != r->width || l->height != r->height)
    throw InputError("stereo: the left image is " + std::to_string(l->width) + "x" +
                     std::to_string(l->height) + " but the right one " +
                     std::to_string(r->width) + "x" + std::to_string(r->height));
  // A raw pair (EuRoC) is rectified here, with maps computed once per calibration.
  const bool raw_pair = StereoRectifier::needed(*cam);
  if (raw_pair) {
    if (cam->width != l->width || cam->height != l->height)
      throw InputError("stereo: the calibration is for " + std::to_string(cam->width) + "x" +
                       std::to_string(cam->height) + " images, the pair is " +
                       std::to_string(l->width) + "x" + std::to_string(l->height));
    rectifier_.prepare(*cam);
    cam = &rectifier_.rectified();
  }
  if (!(cam->baseline > 0) || !(cam->fx > 0) || !(cam->fy > 0))
    throw InputError("stereo: calibration '" + camera.name() +
                     "' needs fx, fy > 0 and a baseline > 0, or a second camera to rectify with");
  configure();  // cheap; picks up parameters changed at run time
  cv::Mat gl = greyOf(*l), gr = greyOf(*r);
  auto t0 = std::chrono::steady_clock::now();
  if (raw_pair) {
    rectifier_.rectify(gl, gr, rect_l_, rect_r_);
    gl = rect_l_;
    gr = rect_r_;
  }
  extractor_.extract(gl, kl_, dl_);
  right_extractor_.extract(gr, kr_, dr_);
  extraction_s_ += secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  StereoMatchOptions mo;
  mo.min_disparity = min_disparity();
  mo.max_disparity = std::min<double>(l->width, cam->fx * cam->baseline / min_depth());
  mo.row_tolerance = row_tolerance();
  mo.max_hamming = max_hamming();
  mo.scale_factor = scale_factor();
  StereoMatcher::match(gl, gr, kl_, dl_, kr_, dr_, mo, disparity_);

  FeatureSet& f = output.emplace(frame);
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
  f.max_scale = maxScale();
  f.reserve(kl_.size());
  // A rectified pair's pixels are the rectified image's: colours come from it, in grey.
  const bool rgb = l->channels >= 3 && !raw_pair;
  for (size_t i = 0; i < kl_.size(); ++i) {
    const int x = cvRound(kl_[i].pt.x), y = cvRound(kl_[i].pt.y);
    uint32_t colour;
    if (rgb) {
      colour = colourAt(*l, x, y);
    } else {
      const uint32_t g = gl.at<uint8_t>(y, x);
      colour = (g << 16) | (g << 8) | g;
    }
    // A keypoint of pyramid scale s is located, and matched along its row, s times less
    // precisely.
    const double scale = keypointScale(kl_[i]);
    f.pushStereo(Eigen::Vector2d(kl_[i].pt.x, kl_[i].pt.y), pixel_sigma() * scale, disparity_[i],
                 disparity_sigma() * scale, dl_.ptr<uint8_t>(static_cast<int>(i)), colour, scale);
  }
  matching_s_ += secondsSince(t0);
  ++frames_;
  keypoints_ += f.size();
  for (double q : f.inverse_depth) with_depth_ += q > 0;
  return true;
}

}  // namespace visual
}  // namespace plugslam
