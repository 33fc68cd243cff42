#include "orb_features.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace plugslam {
namespace visual {

OrbExtractor::OrbExtractor() { setOptions(OrbOptions()); }

void OrbExtractor::setOptions(const OrbOptions& o) {
  options_ = o;
  if (!orb_) {
    // One pyramid level: keypoints come from our own FAST pass; ORB only describes them.
    orb_ = cv::ORB::create(o.features, 1.2f, 1, border(), 0, 2, cv::ORB::FAST_SCORE, 31,
                           o.fast_threshold);
  }
}

double OrbExtractor::levelScale(int level) const {
  return std::pow(options_.scale_factor, static_cast<double>(level));
}

int OrbExtractor::levelFeatures(int level) const {
  const int levels = std::max(1, options_.levels);
  if (levels == 1) return options_.features;
  // A geometric share per level, as ORB-SLAM: level l gets f^l of level 0's, f = 1/scale_factor
  // (a coarser level sees the same scene in fewer pixels; its share shrinks with its side, not
  // its area, so the coarse levels that bridge large scale changes keep enough corners).
  const double f = 1.0 / options_.scale_factor;
  const double first = options_.features * (1.0 - f) / (1.0 - std::pow(f, levels));
  return std::max(1, static_cast<int>(std::lround(first * std::pow(f, level))));
}

void OrbExtractor::detect(const cv::Mat& grey, int features, std::vector<cv::KeyPoint>& out) {
  out.clear();
  const int b = border();
  if (grey.cols <= 2 * b || grey.rows <= 2 * b) return;
  const cv::Rect inner(b, b, grey.cols - 2 * b, grey.rows - 2 * b);
  const cv::Mat roi = grey(inner);
  const int side = std::max(8, options_.cell);
  const int cols = (inner.width + side - 1) / side, rows = (inner.height + side - 1) / side;
  const int per_cell = std::max(1, (features + cols * rows - 1) / (cols * rows));
  cells_.assign(static_cast<size_t>(cols) * static_cast<size_t>(rows), {});
  auto bucket = [&](const std::vector<cv::KeyPoint>& kps) {
    for (auto& c : cells_) c.clear();
    for (size_t i = 0; i < kps.size(); ++i) {
      const int cx = std::min(cols - 1, static_cast<int>(kps[i].pt.x) / side);
      const int cy = std::min(rows - 1, static_cast<int>(kps[i].pt.y) / side);
      cells_[static_cast<size_t>(cy * cols + cx)].push_back(static_cast<int>(i));
    }
  };
  cv::FAST(roi, strong_, options_.fast_threshold, true);
  bucket(strong_);
  std::vector<char> weak_cell(cells_.size(), 0);
  bool need_weak = false;
  for (size_t c = 0; c < cells_.size(); ++c) {
    if (!cells_[c].empty()) continue;
    weak_cell[c] = 1;
    need_weak = true;
  }
  auto keepBest = [&](const std::vector<cv::KeyPoint>& kps, size_t c) {
    std::vector<int>& idx = cells_[c];
    const size_t n = std::min(idx.size(), static_cast<size_t>(per_cell));
    std::partial_sort(idx.begin(), idx.begin() + static_cast<std::ptrdiff_t>(n), idx.end(),
                      [&](int a, int bb) { return kps[a].response > kps[bb].response; });
    for (size_t k = 0; k < n; ++k) {
      cv::KeyPoint kp = kps[idx[k]];
      kp.pt.x += static_cast<float>(b);
      kp.pt.y += static_cast<float>(b);
      kp.angle = options_.upright ? 0.0f : -1.0f;
      kp.octave = 0;
      out.push_back(kp);
    }
  };
  for (size_t c = 0; c < cells_.size(); ++c)
    if (!weak_cell[c]) keepBest(strong_, c);
  if (need_weak && options_.min_fast_threshold < options_.fast_threshold) {
    // Only the empty cells are searched again: a pass at the low threshold over the whole image
    // costs more than the first one (most pixels pass the quick test) and its corners elsewhere
    // would be discarded anyway. Each cell's window grows by FAST's 3-pixel circle, so every
    // pixel of the cell can be a corner.
    constexpr int kCircle = 3;
    for (size_t c = 0; c < cells_.size(); ++c) {
      if (!weak_cell[c]) continue;
      const int x0 = static_cast<int>(c % static_cast<size_t>(cols)) * side;
      const int y0 = static_cast<int>(c / static_cast<size_t>(cols)) * side;
      const cv::Rect cell(x0, y0, std::min(side, inner.width - x0), std::min(side, inner.height - y0));
      const cv::Rect window = cv::Rect(cell.x - kCircle, cell.y - kCircle, cell.width + 2 * kCircle,
                                       cell.height + 2 * kCircle) &
                              cv::Rect(0, 0, inner.width, inner.height);
      cv::FAST(roi(window), weak_, options_.min_fast_threshold, true);
      std::vector<int>& idx = cells_[c];
      idx.clear();
      for (size_t i = 0; i < weak_.size(); ++i) {
        weak_[i].pt.x += static_cast<float>(window.x);
        weak_[i].pt.y += static_cast<float>(window.y);
        if (cell.contains(cv::Point(static_cast<int>(weak_[i].pt.x), static_cast<int>(weak_[i].pt.y))))
          idx.push_back(static_cast<int>(i));
      }
      keepBest(weak_, c);
    }
  }
  if (!options_.upright) {
    // Intensity-centroid orientation over a radius-15 disc (as ORB's own detector does), in the
    // keypoint's own level: the disc covers the same patch the descriptor is taken over.
    for (cv::KeyPoint& kp : out) {
      double m01 = 0, m10 = 0;
      const int x0 = cvRound(kp.pt.x), y0 = cvRound(kp.pt.y);
      for (int dy = -15; dy <= 15; ++dy) {
        const int w = static_cast<int>(std::sqrt(225.0 - dy * dy));
        const uint8_t* row = grey.ptr<uint8_t>(y0 + dy);
        for (int dx = -w; dx <= w; ++dx) {
          const double v = row[x0 + dx];
          m10 += dx * v;
          m01 += dy * v;
        }
      }
      kp.angle = static_cast<float>(std::atan2(m01, m10) * 180.0 / CV_PI);
      if (kp.angle < 0) kp.angle += 360.0f;
    }
  }
}

void OrbExtractor::extract(const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints,
                           cv::Mat& descriptors) {
  keypoints.clear();
  descriptors.release();
  const int b = border();
  if (grey.cols <= 2 * b || grey.rows <= 2 * b) return;
  const int levels = std::max(1, options_.levels);
  if (levels == 1) {
    // Full resolution only: no pyramid, no copy.
    const auto t0 = std::chrono::steady_clock::now();
    detect(grey, options_.features, keypoints);
    const auto t1 = std::chrono::steady_clock::now();
    orb_->compute(grey, keypoints, descriptors);
    detection_s_ += std::chrono::duration<double>(t1 - t0).count();
    description_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    return;
  }
  pyramid_.resize(static_cast<size_t>(levels));
  std::vector<cv::Mat> level_descriptors;
  for (int l = 0; l < levels; ++l) {
    const auto t0 = std::chrono::steady_clock::now();
    const double s = levelScale(l);
    cv::Mat image;
    if (l == 0) {
      image = grey;
    } else {
      // Each level from the one below (area-preserving linear shrink, as ORB-SLAM): a level
      // smaller than the descriptor pattern ends the pyramid.
      const cv::Size size(cvRound(grey.cols / s), cvRound(grey.rows / s));
      if (size.width <= 2 * b || size.height <= 2 * b) break;
      cv::resize(pyramid_[static_cast<size_t>(l - 1)], pyramid_[static_cast<size_t>(l)], size, 0,
                 0, cv::INTER_LINEAR);
      image = pyramid_[static_cast<size_t>(l)];
    }
    if (l == 0) pyramid_[0] = grey;
    detect(image, levelFeatures(l), level_kps_);
    const auto t1 = std::chrono::steady_clock::now();
    // Described in the level's own pixels, where the 31-pixel ORB patch covers s times as much
    // of the full-resolution image.
    if (!level_kps_.empty()) orb_->compute(image, level_kps_, level_desc_);
    const auto t2 = std::chrono::steady_clock::now();
    detection_s_ += std::chrono::duration<double>(t1 - t0).count();
    description_s_ += std::chrono::duration<double>(t2 - t1).count();
    if (level_kps_.empty() || level_desc_.rows != static_cast<int>(level_kps_.size())) continue;
    // Level pixel centres to full resolution: cv::resize maps destination pixel x to source
    // position (x + 0.5) s - 0.5.
    const float fs = static_cast<float>(s);
    for (cv::KeyPoint kp : level_kps_) {
      kp.pt.x = (kp.pt.x + 0.5f) * fs - 0.5f;
      kp.pt.y = (kp.pt.y + 0.5f) * fs - 0.5f;
      kp.size *= fs;
      kp.octave = l;
      keypoints.push_back(kp);
    }
    level_descriptors.push_back(level_desc_.clone());
  }
  pyramid_[0].release();  // a view of the caller's image: not kept past the call
  if (!level_descriptors.empty()) cv::vconcat(level_descriptors, descriptors);
}

}  // namespace visual
}  // namespace plugslam
