// The landmark cue's value types: consistency checks, pruning and archive round trips.
#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "plugslam/archive.h"
#include "plugslam/errors.h"
#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_map.h"
#include "plugslam/property_container.h"
#include "round_trip.h"

namespace plugslam {
namespace {

FeatureSet sample() {
  FeatureSet f;
  f.camera = {500, 500, 320, 240, 0.1};
  f.width = 640;
  f.height = 480;
  f.mount.translation() << 0.1, 0.2, 0.3;
  uint8_t d[32];
  for (int i = 0; i < 5; ++i) {
    for (int k = 0; k < 32; ++k) d[k] = static_cast<uint8_t>(i * 32 + k);
    f.pushStereo(Eigen::Vector2d(100 + i, 200 - i), 1.0, i == 2 ? 0.0 : 10.0 + i, 0.5, d,
                 0x010203u * static_cast<uint32_t>(i));
  }
  return f;
}

TEST(HammingDistance, CountsDifferingBits) {
  uint8_t a[32] = {}, b[32] = {};
  EXPECT_EQ(hammingDistance(a, b, 32), 0);
  b[0] = 0xff;
  b[31] = 0x01;
  EXPECT_EQ(hammingDistance(a, b, 32), 9);
  // Lengths that are not a multiple of 8 (AKAZE: 61 bytes) count their tail too.
  uint8_t c[61] = {}, e[61] = {};
  e[60] = 0x0f;
  EXPECT_EQ(hammingDistance(c, e, 61), 4);
}

TEST(HammingDistance, TheInlineBitCountAgreesWithABitByBitCount) {
  // popcount64 is the CPU's instruction or an inline count depending on the build's target.
  std::mt19937_64 rng(7);
  for (int i = 0; i < 1000; ++i) {
    const uint64_t x = i < 2 ? (i == 0 ? 0 : ~uint64_t{0}) : rng();
    int bits = 0;
    for (int k = 0; k < 64; ++k) bits += static_cast<int>((x >> k) & 1u);
    ASSERT_EQ(popcount64(x), bits) << std::hex << x;
  }
}

TEST(FeatureSet, RoundTripsThroughBothArchives) {
  const FeatureSet f = sample();
  for (ArchiveFormat format : {ArchiveFormat::kBinary, ArchiveFormat::kText}) {
    PropertyContainer c;
    c.set<FeatureSet>("features", f);
    const PropertyContainer back = plugslam::testing::roundTrip(format, c);
    const FeatureSet& g = back.get<FeatureSet>("features");
    ASSERT_EQ(g.size(), f.size());
    EXPECT_EQ(g.descriptors, f.descriptors);
    EXPECT_EQ(g.colours, f.colours);
    EXPECT_FALSE(g.hasDepth(2));
    EXPECT_TRUE(g.hasDepth(3));
    EXPECT_NEAR((g.points[3] - f.points[3]).norm(), 0, 1e-12);
    EXPECT_NEAR((g.covariances[4] - f.covariances[4]).norm(), 0, 1e-12);
    EXPECT_NEAR((g.mount.translation() - f.mount.translation()).norm(), 0, 1e-12);
    EXPECT_DOUBLE_EQ(g.camera.baseline, 0.1);
  }
}

TEST(FeatureSet, InconsistentArraysAreAnError) {
  FeatureSet f = sample();
  f.descriptors.pop_back();
  EXPECT_THROW(f.checkConsistent(), InputError);
  FeatureSet mono;
  const uint8_t d[32] = {};
  EXPECT_THROW(mono.pushStereo(Eigen::Vector2d(1, 1), 1, 5, 0.5, d, 0), InputError);
}

TEST(LandmarkMap, KeepOnlyCompactsEveryArray) {
  LandmarkMap m;
  uint8_t d[32];
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 32; ++k) d[k] = static_cast<uint8_t>(i);
    m.push(Eigen::Vector3d(i, 0, 0), Eigen::Matrix3d::Identity() * i, 10 + i, d, i, 100 + i);
  }
  const uint64_t before = m.revision;
  m.keepOnly({true, false, false, true});
  ASSERT_EQ(m.size(), 2u);
  EXPECT_NE(m.revision, before);
  EXPECT_EQ(m.ids, (std::vector<uint64_t>{10, 13}));
  EXPECT_EQ(m.descriptor(1)[0], 3);
  EXPECT_EQ(m.last_seen[1], 103u);
  EXPECT_DOUBLE_EQ(m.positions[1].x(), 3);
  EXPECT_NO_THROW(m.checkConsistent());
  EXPECT_THROW(m.keepOnly({true}), InputError);

  std::stringstream s;
  {
    auto out = makeOutArchive(s, ArchiveFormat::kBinary);
    save(*out, m);
    out->finish();
  }
  LandmarkMap back;
  auto in = makeInArchive(s, ArchiveFormat::kBinary);
  load(*in, back);
  EXPECT_EQ(back.ids, m.ids);
  EXPECT_EQ(back.descriptors, m.descriptors);
  EXPECT_NEAR((back.covariances[1] - m.covariances[1]).norm(), 0, 1e-12);
}

}  // namespace
}  // namespace plugslam
