#pragma once
// A seeded random source whose streams are identical on every platform: std::mt19937_64 is fully
// specified by the standard, the mappings to uniform and normal numbers below are our own (the
// standard library's distributions are implementation-defined).
#include <cmath>
#include <cstdint>
#include <random>

namespace plugslam {
namespace sim {
namespace sim2d {

/// Portable random numbers: uniform in [0,1) and standard normal via Box-Muller.
class Rng {
 public:
  /// Seeds the generator; `stream` decorrelates independent consumers sharing one user seed.
  explicit Rng(uint64_t seed = 0, uint64_t stream = 0) : engine_(mix(seed, stream)) {}

  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0); }

  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

  /// Uniform integer in [0, n) (n > 0); the modulo bias is below 2^-40 for n < 2^24.
  uint64_t index(uint64_t n) { return engine_() % n; }

  /// Standard normal sample (Box-Muller, the second value of each pair is kept for the next call).
  double gaussian() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u1 = uniform();
    while (u1 <= 0.0) u1 = uniform();
    const double u2 = uniform();
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * M_PI * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

  /// Normal sample with the given standard deviation (0 returns exactly 0 without drawing).
  double gaussian(double sigma) { return sigma > 0.0 ? sigma * gaussian() : 0.0; }

  /// True with probability p (p <= 0 never draws).
  bool bernoulli(double p) { return p > 0.0 && uniform() < p; }

 private:
  // splitmix64 finaliser: nearby (seed, stream) pairs give unrelated engine seeds.
  static uint64_t mix(uint64_t seed, uint64_t stream) {
    uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
