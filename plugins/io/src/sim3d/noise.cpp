#include "sim3d/noise.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "plugslam/errors.h"
#include "sim2d/random.h"

namespace plugslam {
namespace io {
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
  double uniform() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  // A standard normal from a fixed table of 65536 Box-Muller samples with a random sign: a few
  // nanoseconds per pixel, and 131072 distinct values are plenty for sensor noise.
  double gaussian() {
    const uint64_t r = next();
    const double g = table()[r & 65535];
    return (r >> 63) ? -g : g;
  }

 private:
  static const std::vector<double>& table() {
    static const std::vector<double> t = [] {
      std::vector<double> v(65536);
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
  if (!(grazing_deg > 0 && grazing_deg <= 90)) throw InputError("depth noise: grazing_deg must be in (0, 90]");
  if (!(dropout >= 0 && dropout <= 1)) throw InputError("depth noise: dropout must be in [0, 1]");
  if (quantize && (!(disparity_baseline > 0) || !(disparity_focal > 0) || !(subpixel > 0)))
    throw InputError("depth noise: quantisation needs positive baseline, focal and subpixel");
}

void ImageNoise::validate() const {
  if (!(sigma >= 0)) throw InputError("image noise: sigma must be >= 0");
  if (!(gain_sigma >= 0 && gain_sigma < 2)) throw InputError("image noise: gain_sigma must be in [0, 2)");
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
    const double g = rng.gaussian();
    const double u = rng.uniform();
    if (z <= 0.0 || z < noise.min_range || z > noise.max_range ||
        buf.incidence[i] < cos_grazing || u < noise.dropout) {
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
  for (int y = 0; y < image->height; ++y) {
    uint8_t* row = &image->data[static_cast<size_t>(y) * image->stride];
    for (int x = 0; x < image->width * image->channels; ++x) {
      const double v = gain * row[x] + noise.sigma * rng.gaussian();
      row[x] = static_cast<uint8_t>(std::clamp(v + 0.5, 0.0, 255.0));
    }
  }
}

}  // namespace sim3d
}  // namespace io
}  // namespace plugslam
