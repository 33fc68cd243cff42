#include "sim3d/noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "plugslam/errors.h"
#include "sim2d/random.h"

namespace plugslam {
namespace sim {
namespace sim3d {
namespace {

// A fast per-pixel generator: splitmix64 is fully specified, so streams are portable.
class FastRng {
 public:
  FastRng(uint64_t seed, uint64_t frame, uint64_t stream)
      : state_(seed * 0x9E3779B97F4A7C15ull ^ (frame + 1) * 0xBF58476D1CE4E5B9ull ^
               (stream + 7) * 0x94D049BB133111EBull) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Standard normals from a fixed table of 4096 Box-Muller samples (32 KB: stays in L1 cache)
  // with a random sign: 8192 distinct values, plenty for sensor noise. One 64-bit draw gives
  // four samples (13 bits each) and 12 spare bits.
  static double tableNormal(uint64_t bits13) {
    const double g = table()[bits13 & 4095];
    return (bits13 & 4096) ? -g : g;
  }

 private:
  static const std::vector<double>& table() {
    static const std::vector<double> t = [] {
      std::vector<double> v(4096);
      sim2d::Rng rng(0x5eed, 0);
      for (double& x : v) x = rng.gaussian();
      return v;
    }();
    return t;
  }
  uint64_t state_;
};

}  // namespace

void DepthNoise::validate() const {
  if (!(sigma_a >= 0) || !(sigma_b >= 0)) throw InputError("depth noise: sigmas must be >= 0");
  if (!(min_range >= 0) || !(max_range > min_range))
    throw InputError("depth noise: expected 0 <= min_range < max_range");
  if (!(grazing_deg > 0 && grazing_deg <= 90))
    throw InputError("depth noise: grazing_deg must be in (0, 90]");
  if (!(dropout >= 0 && dropout <= 1)) throw InputError("depth noise: dropout must be in [0, 1]");
  if (quantize && (!(disparity_baseline > 0) || !(disparity_focal > 0) || !(subpixel > 0)))
    throw InputError("depth noise: quantisation needs positive baseline, focal and subpixel");
}

void ImageNoise::validate() const {
  if (!(sigma >= 0)) throw InputError("image noise: sigma must be >= 0");
  if (!(gain_sigma >= 0 && gain_sigma < 2))
    throw InputError("image noise: gain_sigma must be in [0, 2)");
  if (!(gain_period > 0)) throw InputError("image noise: gain_period must be positive");
}

double exposureGain(const ImageNoise& noise, uint64_t seed, double stamp) {
  if (!noise.enabled || noise.gain_sigma == 0.0) return 1.0;
  // Three sinusoids with seeded frequencies and phases: smooth, bounded, random-access in time.
  sim2d::Rng rng(seed, 77);
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double period = noise.gain_period * rng.uniform(0.5, 2.0) * (k + 1);
    const double phase = rng.uniform(0.0, 2.0 * M_PI);
    sum += std::sin(2.0 * M_PI * stamp / period + phase);
  }
  return std::exp(noise.gain_sigma * sum / std::sqrt(1.5));
}

void makeDepthImage(const RenderBuffers& buf, const DepthNoise& noise, uint64_t seed,
                    uint64_t frame, DepthImage* depth) {
  depth->resize(buf.width, buf.height);
  const size_t n = buf.depth.size();
  if (!noise.enabled) {
    for (size_t i = 0; i < n; ++i) depth->data[i] = static_cast<float>(buf.depth[i]);
    return;
  }
  FastRng rng(seed, frame, 1);
  const double cos_grazing = std::cos(noise.grazing_deg * M_PI / 180.0);
  const double bf = noise.disparity_baseline * noise.disparity_focal;
  for (size_t i = 0; i < n; ++i) {
    double z = buf.depth[i];
    const uint64_t r = rng.next();  // 13 bits for the normal, 51 for the dropout uniform
    const double g = FastRng::tableNormal(r);
    const double u = static_cast<double>(r >> 13) * (1.0 / 2251799813685248.0);
    if (z <= 0.0 || z < noise.min_range || z > noise.max_range || buf.incidence[i] < cos_grazing ||
        u < noise.dropout) {
      depth->data[i] = 0.0f;
      continue;
    }
    const double dz = z - noise.z0;
    z += (noise.sigma_a + noise.sigma_b * dz * dz) * g;
    if (noise.quantize) {
      const double d = std::round(bf / z * noise.subpixel) / noise.subpixel;
      z = d > 0.0 ? bf / d : 0.0;
    }
    depth->data[i] = z > 0.0 ? static_cast<float>(z) : 0.0f;
  }
}

void applyImageNoise(const ImageNoise& noise, uint64_t seed, uint64_t frame, uint64_t stream,
                     double gain, Image* image) {
  if (!noise.enabled) return;
  FastRng rng(seed, frame, 100 + stream);
  // Fixed point (1/256 grey level): a gain table over the 256 input values and a noise table
  // over the 8192 normal values make each sample two loads and an add.
  int32_t gain_lut[256];
  for (int v = 0; v < 256; ++v) gain_lut[v] = static_cast<int32_t>(std::lround(gain * v * 256.0));
  static thread_local std::vector<int32_t> noise_lut;
  static thread_local double noise_lut_sigma = -1.0;
  if (noise_lut_sigma != noise.sigma) {
    noise_lut.resize(8192);
    for (uint64_t k = 0; k < 8192; ++k)
      noise_lut[k] =
          static_cast<int32_t>(std::lround(noise.sigma * FastRng::tableNormal(k) * 256.0));
    noise_lut_sigma = noise.sigma;
  }
  const int n = image->width * image->channels;
  for (int y = 0; y < image->height; ++y) {
    uint8_t* row = &image->data[static_cast<size_t>(y) * image->stride];
    uint64_t r = 0;
    for (int x = 0; x < n; ++x) {
      if ((x & 3) == 0) r = rng.next();
      const int32_t v = (gain_lut[row[x]] + noise_lut[r & 8191] + 128) >> 8;
      r >>= 13;
      row[x] = static_cast<uint8_t>(v < 0 ? 0 : (v > 255 ? 255 : v));
    }
  }
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
