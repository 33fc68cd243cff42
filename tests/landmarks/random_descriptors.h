#pragma once
// ORB-sized binary descriptors for the appearance tests: random ones (a corner of its own) and
// copies with bits flipped (the same corner seen from another viewpoint).
#include <array>
#include <cstdint>
#include <random>

namespace plugslam::testing {

/// A 256-bit descriptor.
using Descriptor = std::array<uint8_t, 32>;

/// Uniformly random bits.
inline Descriptor randomDescriptor(std::mt19937& rng) {
  std::uniform_int_distribution<int> byte(0, 255);
  Descriptor d;
  for (auto& b : d) b = static_cast<uint8_t>(byte(rng));
  return d;
}

/// `d` with `flips` random bits flipped (a bit may be drawn twice).
inline Descriptor perturbed(Descriptor d, int flips, std::mt19937& rng) {
  std::uniform_int_distribution<int> bit(0, 255);
  for (int i = 0; i < flips; ++i) {
    const int b = bit(rng);
    d[static_cast<size_t>(b >> 3)] ^= static_cast<uint8_t>(1u << (b & 7));
  }
  return d;
}

}  // namespace plugslam::testing
