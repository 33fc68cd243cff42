#include "stereo_matcher.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "plugslam/landmarks/feature_set.h"

namespace plugslam {
namespace visual {

double StereoMatcher::refine(const cv::Mat& left, const cv::Mat& right, int ul, int v, int ur0,
                             int w, int search) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (v - w < 0 || v + w >= left.rows || ul - w < 0 || ul + w >= left.cols) return nan;
  if (ur0 - search - w < 0 || ur0 + search + w >= right.cols) return nan;
  // Zero-mean windows: the two cameras' exposures need not agree. With n pixels a window, the
  // cost n * SAD = sum |(n l - sum l) - (n r - sum r)| is exact in integers, and the minimum and
  // its parabola below are the same for any positive scale of the costs. The windows are copied
  // into contiguous arrays so that the sums run over one vectorizable loop.
  constexpr int kMaxSide = 15, kMaxSearch = 8;  // StereoMatchOptions: window 5, search 3
  const int side = 2 * w + 1;
  if (side > kMaxSide || search > kMaxSearch) return nan;
  const int n = side * side;
  using Window = std::array<int32_t, kMaxSide * kMaxSide>;
  Window a{}, b{};
  const auto copyWindow = [&](const cv::Mat& image, int u, Window& out) {
    int sum = 0;
    for (int y = -w, k = 0; y <= w; ++y) {
      const uint8_t* p = image.ptr<uint8_t>(v + y) + u - w;
      for (int x = 0; x < side; ++x, ++k) {
        out[static_cast<size_t>(k)] = n * p[x];
        sum += p[x];
      }
    }
    return sum;
  };
  const int sum_l = copyWindow(left, ul, a);
  for (int k = 0; k < n; ++k) a[static_cast<size_t>(k)] -= sum_l;
  std::array<double, 2 * kMaxSearch + 1> cost{};
  for (int s = -search; s <= search; ++s) {
    const int sum_r = copyWindow(right, ur0 + s, b);
    int32_t sad = 0;
    for (int k = 0; k < n; ++k)
      sad += std::abs(a[static_cast<size_t>(k)] - b[static_cast<size_t>(k)] + sum_r);
    cost[static_cast<size_t>(s + search)] = sad;
  }
  int best = 0;
  for (int k = 1; k < 2 * search + 1; ++k)
    if (cost[static_cast<size_t>(k)] < cost[static_cast<size_t>(best)]) best = k;
  if (best == 0 || best == 2 * search) return nan;
  const double c0 = cost[static_cast<size_t>(best - 1)], c1 = cost[static_cast<size_t>(best)],
               c2 = cost[static_cast<size_t>(best + 1)];
  const double denom = c0 - 2 * c1 + c2;
  const double delta = denom > 0 ? 0.5 * (c0 - c2) / denom : 0.0;
  if (std::abs(delta) > 1.0) return nan;
  return ur0 + (best - search) + delta;
}

void StereoMatcher::match(const cv::Mat& left, const cv::Mat& right,
                          const std::vector<cv::KeyPoint>& lk, const cv::Mat& ld,
                          const std::vector<cv::KeyPoint>& rk, const cv::Mat& rd,
                          const StereoMatchOptions& o, std::vector<double>& disparity) {
  disparity.assign(lk.size(), -1.0);
  if (lk.empty() || rk.empty()) return;
  // Right keypoints by row.
  std::vector<std::vector<int>> rows(static_cast<size_t>(right.rows));
  for (size_t j = 0; j < rk.size(); ++j) {
    const int y = cvRound(rk[j].pt.y);
    if (y >= 0 && y < right.rows) rows[static_cast<size_t>(y)].push_back(static_cast<int>(j));
  }
  const int bytes = ld.cols;
  for (size_t i = 0; i < lk.size(); ++i) {
    const double ul = lk[i].pt.x;
    const int v = cvRound(lk[i].pt.y);
    const double umin = ul - o.max_disparity, umax = ul - o.min_disparity;
    int best = -1, best_d = o.max_hamming + 1;
    // A coarse pyramid keypoint's row is known only to its level's pixel; a partner must come
    // from the same or a neighbouring level (its descriptor is of the same patch size).
    const int octave = lk[i].octave;
    const int tolerance =
        static_cast<int>(std::ceil(o.row_tolerance * std::pow(o.scale_factor, octave)));
    for (int y = std::max(0, v - tolerance); y <= std::min(right.rows - 1, v + tolerance); ++y) {
      for (int j : rows[static_cast<size_t>(y)]) {
        const double ur = rk[static_cast<size_t>(j)].pt.x;
        if (ur < umin || ur > umax) continue;
        if (std::abs(rk[static_cast<size_t>(j)].octave - octave) > 1) continue;
        const int d = hammingDistance(ld.ptr<uint8_t>(static_cast<int>(i)), rd.ptr<uint8_t>(j), bytes);
        if (d < best_d) {
          best_d = d;
          best = j;
        }
      }
    }
    if (best < 0) continue;
    const double ur = refine(left, right, cvRound(ul), v, cvRound(rk[static_cast<size_t>(best)].pt.x),
                             o.window, o.search);
    if (!std::isfinite(ur)) continue;
    const double d = ul - ur;
    if (d >= o.min_disparity && d <= o.max_disparity) disparity[i] = d;
  }
}

}  // namespace visual
}  // namespace plugslam
