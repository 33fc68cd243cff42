#pragma once
// PreProcessor: turns raw readings into one cue of the measurement container. It declares the raw
// entries it reads (Input<T>, Container::raw) and the measurement entries it writes (Output<T>,
// Container::measurement), so the builder can check that every slice's measurement is written.
#include "plugslam/configurable.h"
#include "plugslam/entry.h"
#include "plugslam/frame.h"

namespace plugslam {
inline namespace abi_v1 {

/// Reads from `frame.raw` and writes one (or more) entries of `frame.measurement`.
class PreProcessor : public Configurable {
 public:
  static constexpr const char* kKind = "PreProcessor";
  ~PreProcessor() override;
  /// Processes one frame. Returns false when the reading is unusable (the cue is then absent).
  virtual bool process(Frame& frame) = 0;
};

}  // namespace abi_v1
}  // namespace plugslam
