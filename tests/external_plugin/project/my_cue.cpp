// An out-of-tree plugin: a preprocessor that copies a raw value into the measurement, and an
// aligner slice that aligns measured landmarks to the local map's, matched by index.
#include <plugslam/aligner_slice.h>
#include <plugslam/plugin.h>
#include <plugslam/preprocessor.h>

#include <algorithm>
#include <vector>

namespace mycue {

using plugslam::Container;

class Echo : public plugslam::PreProcessor {
 public:
  plugslam::Input<double> input{this, Container::raw, "input", "value", "raw value to copy"};
  plugslam::Output<double> output{this, Container::measurement, "output", "echo",
                                  "measurement entry to write"};

  void configure() override {  // after the YAML is applied: check invariants
    if (input.name().empty()) throw plugslam::ParamError("input", "must name a raw entry");
  }
  bool process(plugslam::Frame& frame) override {
    const double* v = input.find(frame);
    if (!v) return false;  // the reading is absent this frame
    output.set(frame, *v);
    return true;
  }
};

using Points = std::vector<Eigen::Vector2d>;

class LandmarkSlice : public plugslam::AlignerSlice<plugslam::Space2D> {
 public:
  plugslam::Input<Points> measurement{this, Container::measurement, "measurement", "landmarks",
                                      "landmarks seen, robot frame"};
  plugslam::Input<Points> scene{this, Container::scene, "scene", "landmarks",
                                "landmarks mapped, local-map frame"};
  plugslam::Param<double> sigma{this, "sigma", 0.05, "m", "landmark position noise",
                                plugslam::Range{1e-6, 10}};

  // Called with both entries bound; absent entries skip the slice for the frame.
  void linearize(const Pose& t, plugslam::NormalEquations<plugslam::Space2D>& eq) const override {
    const size_t n = std::min(measurement->size(), scene->size());
    eq.candidates = measurement->size();
    for (size_t i = 0; i < n; ++i)
      eq.add(plugslam::PointToPoint2D{(*measurement)[i], (*scene)[i]}, t, 1 / (sigma() * sigma()));
  }
};

}  // namespace mycue

PLUGSLAM_PLUGIN("mycue", "0.3.0", "an out-of-tree example cue") {
  registrar.add<mycue::Echo>("Echo", "copies a raw value into the measurement");
  registrar.add<mycue::LandmarkSlice>("LandmarkSlice", "aligns landmarks matched by index");
}
