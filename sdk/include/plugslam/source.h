#pragma once
// Source: where frames come from (dataset readers, simulators). A source may declare the raw
// entries it writes (Output<T> members, Container::raw, or provides() for names known only after
// configure()); one that declares any is taken to declare all, and the builder then checks every
// raw entry the pipeline reads against them.
#include <cstdint>
#include <string>
#include <typeindex>
#include <vector>

#include "plugslam/configurable.h"
#include "plugslam/entry.h"
#include "plugslam/frame.h"

namespace plugslam {
inline namespace abi_v1 {

/// A raw entry a source writes: its name and value type.
struct ProvidedEntry {
  std::string name;     ///< the property's name in Frame::raw
  std::type_index type;  ///< its value type
};

/// Produces one synchronised raw frame per call.
class Source : public Configurable {
 public:
  static constexpr const char* kKind = "Source";
  ~Source() override;
  /// Fills `frame.raw` and `frame.stamp` with the next time step; false at the end of the data.
  virtual bool next(Frame& frame) = 0;
  /// Number of frames when known in advance (for progress), or -1.
  virtual int64_t sizeHint() const { return -1; }
  /// The raw entries the source writes, known after configure(); empty when it does not say
  /// (nothing is then checked). The default lists its Output<T> members of Container::raw.
  virtual std::vector<ProvidedEntry> provides() const;
};

}  // namespace abi_v1
}  // namespace plugslam
