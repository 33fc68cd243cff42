// An out-of-tree plugin: one preprocessor that copies a raw value into the measurement.
#include <plugslam/plugin.h>
#include <plugslam/preprocessor.h>

namespace mycue {

class Echo : public plugslam::PreProcessor {
 public:
  plugslam::Param<std::string> input{this, "input", "value", "", "raw entry to copy"};
  plugslam::Param<std::string> output{this, "output", "echo", "", "measurement entry to write"};
  bool process(plugslam::Frame& frame) override {
    const double* v = frame.raw.find<double>(input());
    if (!v) return false;
    frame.measurement.set<double>(output(), *v);
    return true;
  }
};

}  // namespace mycue

PLUGSLAM_PLUGIN("mycue", "0.3.0", "an out-of-tree example cue") {
  registrar.add<mycue::Echo>("Echo", "copies a raw value into the measurement");
}
