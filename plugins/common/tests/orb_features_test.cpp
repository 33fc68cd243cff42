// The shared keypoint extractor's image pyramid: a view from twice as near matches the far one
// through the pyramid, at the right place and the right scale, where one scale does not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "orb_features.h"
#include "plugslam/landmarks/feature_set.h"

namespace plugslam {
namespace {

// A random texture with blobs of several sizes (corners at every scale), 8-bit grey.
cv::Mat texture(int width, int height) {
  cv::Mat sum(height, width, CV_32F, cv::Scalar(0));
  std::mt19937 rng(7);
  for (double sigma : {2.0, 5.0, 12.0}) {
    cv::Mat noise(height, width, CV_32F);
    cv::randu(noise, 0.0, 1.0);
    cv::GaussianBlur(noise, noise, cv::Size(0, 0), sigma);
    cv::normalize(noise, noise, -1.0, 1.0, cv::NORM_MINMAX);
    sum += noise;
  }
  cv::Mat out;
  cv::normalize(sum, sum, 0.0, 255.0, cv::NORM_MINMAX);
  sum.convertTo(out, CV_8U);
  return out;
}

struct Views {
  cv::Mat far, near;  // near = the centre of the scene seen from half the distance: twice as big
  // Where a far pixel lands in the near view (cv::resize's pixel-centre convention).
  cv::Point2f toNear(const cv::Point2f& p) const {
    return {(p.x + 0.5f) * 2.0f - 0.5f - 320.0f, (p.y + 0.5f) * 2.0f - 0.5f - 240.0f};
  }
};

Views views() {
  const cv::Mat scene = texture(1280, 960);
  Views v;
  cv::resize(scene, v.far, cv::Size(640, 480), 0, 0, cv::INTER_AREA);
  v.near = scene(cv::Rect(320, 240, 640, 480)).clone();
  return v;
}

struct MatchCount {
  int matches = 0;  // mutual nearest descriptors within 64 bits, of far keypoints in the overlap
  int correct = 0;  // of those, at the place the zoom predicts (within 3 of the coarser pixel)
  double octave_gap = 0;  // mean (near octave - far octave) of the correct ones
};

MatchCount matchViews(const Views& v, const visual::OrbOptions& options) {
  visual::OrbExtractor extractor;
  extractor.setOptions(options);
  std::vector<cv::KeyPoint> kf, kn;
  cv::Mat df, dn;
  extractor.extract(v.far, kf, df);
  extractor.extract(v.near, kn, dn);
  EXPECT_EQ(df.rows, static_cast<int>(kf.size()));
  EXPECT_EQ(dn.rows, static_cast<int>(kn.size()));
  auto nearest = [](const cv::Mat& a, int i, const cv::Mat& b, int& best_d) {
    int best = -1;
    best_d = 1 << 20;
    for (int j = 0; j < b.rows; ++j) {
      const int d = hammingDistance(a.ptr<uint8_t>(i), b.ptr<uint8_t>(j), a.cols);
      if (d < best_d) {
        best_d = d;
        best = j;
      }
    }
    return best;
  };
  MatchCount out;
  for (int i = 0; i < df.rows; ++i) {
    int d = 0, back_d = 0;
    const int j = nearest(df, i, dn, d);
    // Only the far view's centre is in the near one: the rest has no true partner.
    const cv::Point2f predicted = v.toNear(kf[static_cast<size_t>(i)].pt);
    if (predicted.x < 0 || predicted.y < 0 || predicted.x > 639 || predicted.y > 479) continue;
    if (j < 0 || d > 64 || nearest(dn, j, df, back_d) != i) continue;
    ++out.matches;
    const cv::Point2f error = kn[static_cast<size_t>(j)].pt - predicted;
    const double pixel = extractor.levelScale(kn[static_cast<size_t>(j)].octave);
    if (std::hypot(error.x, error.y) > 3.0 * pixel) continue;
    ++out.correct;
    out.octave_gap += kn[static_cast<size_t>(j)].octave - kf[static_cast<size_t>(i)].octave;
  }
  if (out.correct > 0) out.octave_gap /= out.correct;
  return out;
}

visual::OrbOptions options(int levels) {
  visual::OrbOptions o;
  o.features = 1200;
  o.upright = false;
  o.levels = levels;
  o.scale_factor = 1.2;
  return o;
}

TEST(FeatureExtractor, PyramidMatchesAViewFromTwiceAsNear) {
  const Views v = views();
  const MatchCount one = matchViews(v, options(1));
  const MatchCount pyramid = matchViews(v, options(8));
  // A 2x zoom is 3.8 levels of 1.2: the near view's corners are found about four levels up.
  // Measured: one scale 0 of 91 mutual matches correct; 8 levels 160 of 208, octave gap 3.84.
  EXPECT_GT(pyramid.correct, 3 * std::max(one.correct, 10))
      << one.correct << " of " << one.matches << " at one scale";
  EXPECT_GT(pyramid.correct, pyramid.matches / 2) << pyramid.matches << " matches";
  std::printf("one scale: %d of %d matches correct; 8 levels: %d of %d, octave gap %.2f\n",
              one.correct, one.matches, pyramid.correct, pyramid.matches, pyramid.octave_gap);
  EXPECT_NEAR(pyramid.octave_gap, std::log(2.0) / std::log(1.2), 1.0);
}

TEST(FeatureExtractor, OneLevelIsFullResolutionOnly) {
  const Views v = views();
  visual::OrbExtractor extractor;
  extractor.setOptions(options(1));
  std::vector<cv::KeyPoint> k;
  cv::Mat d;
  extractor.extract(v.far, k, d);
  ASSERT_GT(k.size(), 500u);
  for (const cv::KeyPoint& kp : k) EXPECT_EQ(kp.octave, 0);
  EXPECT_DOUBLE_EQ(extractor.levelScale(0), 1.0);
}

TEST(FeatureExtractor, LevelsShareTheKeypointsGeometrically) {
  visual::OrbExtractor extractor;
  extractor.setOptions(options(8));
  int total = 0;
  for (int l = 0; l < 8; ++l) {
    total += extractor.levelFeatures(l);
    if (l > 0) {
      EXPECT_LT(extractor.levelFeatures(l), extractor.levelFeatures(l - 1));
    }
  }
  EXPECT_NEAR(total, 1200, 8);
  EXPECT_NEAR(extractor.levelScale(7), std::pow(1.2, 7), 1e-9);
  // Every keypoint of a pyramid lies inside the full-resolution image, with its level's scale.
  const Views v = views();
  std::vector<cv::KeyPoint> k;
  cv::Mat d;
  extractor.extract(v.near, k, d);
  ASSERT_EQ(d.rows, static_cast<int>(k.size()));
  int coarse = 0;
  for (const cv::KeyPoint& kp : k) {
    EXPECT_GE(kp.pt.x, 0.0f);
    EXPECT_LT(kp.pt.x, 640.0f);
    EXPECT_GE(kp.pt.y, 0.0f);
    EXPECT_LT(kp.pt.y, 480.0f);
    coarse += kp.octave >= 4;
  }
  EXPECT_GT(coarse, 50);
}

}  // namespace
}  // namespace plugslam
