// A test plugin that needs no sensor: a robot driving circles through a field of landmarks with
// known identities (tests/modules/landmark_cue.h), with ground truth. It lets the shell and
// session tests run whole SLAM pipelines (tracker, loop closing, graph) through the host.
#include <signal.h>
#include <unistd.h>

#include <cmath>
#include <limits>
#include <random>

#include "landmark_cue.h"
#include "plugslam/plugin.h"
#include "plugslam/preprocessor.h"
#include "plugslam/source.h"

namespace lmsim {

using plugslam::testing::Landmarks;
using namespace plugslam;

/// Drives `laps` circles of radius `radius` from the origin (heading +x, turning left).
class LandmarkSource : public Source {
 public:
  Param<double> radius{this, "radius", 8.0, "m", "radius of the circle", Range{1, 1e3}};
  Param<double> step{this, "step", 0.25, "m", "travel between frames", Range{0.01, 10}};
  Param<double> laps{this, "laps", 2.0, "", "laps driven", Range{0, 100}};
  Param<int> landmarks{this, "landmarks", 600, "", "landmarks scattered around", Range{1, 1e6}};
  Param<double> range{this, "range", 6.0, "m", "sensing range", Range{0.1, 1e3}};
  Param<double> noise{this, "noise", 0.02, "m", "std. dev. of each landmark reading", Range{0, 10}};
  Param<int> seed{this, "seed", 3, "", "random seed", Range{0, 1e9}};
  Param<bool> endless{this, "endless", false, "",
                      "drive on past the last lap until the run is stopped (a run that is always "
                      "mid-way, however fast the machine)"};
  Param<int> interrupt_at{this, "interrupt_at", -1, "",
                          "SIGINT to the process before this frame, as a Ctrl-C (-1: never)",
                          Range{-1, 1e9}};

  void configure() override {
    std::mt19937 rng(static_cast<unsigned>(seed()));
    const double r = radius(), m = range();
    std::uniform_real_distribution<double> ux(-r - m, r + m), uy(-m, 2 * r + m);
    world_.clear();
    for (int i = 0; i < landmarks(); ++i) world_.emplace_back(ux(rng), uy(rng));
    rng_.seed(static_cast<unsigned>(seed()) + 1);
    frames_ = static_cast<int64_t>(std::floor(laps() * 2 * M_PI * r / step())) + 1;
    emitted_ = 0;
  }
  bool next(Frame& frame) override {
    if (!endless() && emitted_ >= frames_) return false;
    // The interrupt at a known frame, whatever the machine's speed: a test needs no timing.
    if (emitted_ == interrupt_at()) ::kill(::getpid(), SIGINT);
    const double phi = emitted_ * step() / radius();
    const Eigen::Isometry2d pose =
        se2(radius() * std::sin(phi), radius() * (1 - std::cos(phi)), phi);
    Landmarks seen = plugslam::testing::observe(world_, pose, range());
    std::normal_distribution<double> n(0.0, 1.0);
    for (auto& p : seen)
      if (p.allFinite()) p += noise() * Eigen::Vector2d(n(rng_), n(rng_));
    frame.stamp = 0.1 * static_cast<double>(emitted_);
    frame.raw.set<Landmarks>("landmarks", std::move(seen));
    frame.raw.set<Eigen::Isometry2d>("ground_truth", pose);
    ++emitted_;
    return true;
  }
  int64_t sizeHint() const override { return endless() ? -1 : frames_; }

 private:
  Landmarks world_;
  std::mt19937 rng_;
  int64_t frames_ = 0, emitted_ = 0;
};

/// Copies the raw landmark reading into the measurement.
class LandmarkCue : public PreProcessor {
 public:
  Input<Landmarks> input{this, Container::raw, "input", "landmarks", "landmark reading"};
  Output<Landmarks> output{this, Container::measurement, "output", "landmarks",
                           "measured landmarks"};
  bool process(Frame& frame) override {
    const Landmarks* l = input.find(frame);
    if (!l) return false;
    output.set(frame, *l);
    return true;
  }
};

/// The landmark aligner slice with a weight instead of a sigma (another type for swap tests).
class WeightedLandmarkSlice : public plugslam::testing::LandmarkSliceBase {
 public:
  Param<double> weight{
      this, "weight", 2500.0, "1/m^2", "information of each landmark", Range{1e-9, 1e12}};

 protected:
  double information() const override { return weight(); }
};

}  // namespace lmsim

PLUGSLAM_PLUGIN("lmsim", "1.0.0", "test: landmark world source, landmark cue and slices") {
  registrar.add<lmsim::LandmarkSource>("LandmarkSource", "circles through a landmark field");
  registrar.add<lmsim::LandmarkCue>("LandmarkCue", "raw landmarks -> measurement");
  registrar.add<plugslam::testing::LandmarkSlice>("LandmarkSlice",
                                                  "landmark aligner slice (sigma)");
  registrar.add<lmsim::WeightedLandmarkSlice>("WeightedLandmarkSlice",
                                              "landmark aligner slice (weight)");
  registrar.add<plugslam::testing::LandmarkMapSlice>("LandmarkMapSlice",
                                                     "adds new landmarks to the scene");
}
