#include "keypoint_preprocessor.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
namespace visual {

KeypointPreprocessor::~KeypointPreprocessor() = default;

OrbOptions KeypointPreprocessor::orbOptions() const {
  OrbOptions o;
  o.features = features();
  o.cell = cell();
  o.fast_threshold = fast_threshold();
  o.min_fast_threshold = min_fast_threshold();
  o.upright = upright();
  o.levels = levels();
  o.scale_factor = scale_factor();
  return o;
}

double KeypointPreprocessor::keypointScale(const cv::KeyPoint& keypoint) const {
  return extractor_.levelScale(keypoint.octave);
}

double KeypointPreprocessor::maxScale() const {
  return extractor_.levelScale(std::max(1, levels()) - 1);
}

void KeypointPreprocessor::configure() {
  if (min_fast_threshold() > fast_threshold())
    throw ParamError("min_fast_threshold",
                     "must not exceed fast_threshold (" + std::to_string(fast_threshold()) + ")");
  extractor_.setOptions(orbOptions());
}

cv::Mat asMat(const Image& im) {
  const int type = im.channels == 1 ? CV_8UC1 : (im.channels == 3 ? CV_8UC3 : CV_8UC4);
  return cv::Mat(im.height, im.width, type, const_cast<uint8_t*>(im.data.data()),
                 static_cast<size_t>(im.stride));
}

cv::Mat greyOf(const Image& im) {
  cv::Mat m = asMat(im);
  if (im.channels == 1) return m;
  cv::Mat grey;
  cv::cvtColor(m, grey, im.channels == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY);
  return grey;
}

uint32_t colourAt(const Image& im, int x, int y) {
  if (im.channels >= 3)
    return (uint32_t(im.at(x, y, 0)) << 16) | (uint32_t(im.at(x, y, 1)) << 8) | im.at(x, y, 2);
  const uint32_t g = im.at(x, y, 0);
  return (g << 16) | (g << 8) | g;
}

}  // namespace visual
}  // namespace plugslam
