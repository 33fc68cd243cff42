#include "orb_features.h"

#include <algorithm>
#include <chrono>
#include <cmath>

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

void OrbExtractor::extract(const cv::Mat& grey, std::vector<cv::KeyPoint>& keypoints,
                           cv::Mat& descriptors) {
  keypoints.clear();
  const int b = border();
  if (grey.cols <= 2 * b || grey.rows <= 2 * b) {
    descriptors.release();
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const cv::Rect inner(b, b, grey.cols - 2 * b, grey.rows - 2 * b);
  const cv::Mat roi = grey(inner);
  const int side = std::max(8, options_.cell);
  const int cols = (inner.width + side - 1) / side, rows = (inner.height + side - 1) / side;
  const int per_cell = std::max(1, (options_.features + cols * rows - 1) / (cols * rows));
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
      keypoints.push_back(kp);
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
    // Intensity-centroid orientation over a radius-15 disc (as ORB's own detector does).
    for (cv::KeyPoint& kp : keypoints) {
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
  const auto t1 = std::chrono::steady_clock::now();
  orb_->compute(grey, keypoints, descriptors);
  detection_s_ += std::chrono::duration<double>(t1 - t0).count();
  description_s_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
}

}  // namespace visual
}  // namespace plugslam
