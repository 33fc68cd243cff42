#pragma once
// PreProcessor: turns raw readings into one cue of the measurement container.
#include "plugslam/configurable.h"
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
