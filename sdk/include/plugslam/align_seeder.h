#pragma once
// AlignSeeder: where the Multi-Aligner's solve could start when the prediction is poor. A
// gradient-based solve only finds the pose near its start; a seeder searches a wide window
// around the prediction (for 2D laser, laser2d.CorrelativeSeeder: a correlative scan-to-map
// search) and proposes starting poses. The aligner runs it only when the solve from the
// prediction fails, or when the tracker finds the solution too far from the prediction (issue 20).
#include <vector>

#include "plugslam/aligner_slice.h"

namespace plugslam {
inline namespace abi_v1 {

/// Proposes starting poses for an alignment from a search of the scene ("AlignSeeder2D/3D").
/// Declares its entries as typed members (Input<T>), bound like an AlignerSlice's.
template <class S>
class AlignSeeder : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "AlignSeeder2D" : "AlignSeeder3D";
  using Pose = typename S::Pose;
  ~AlignSeeder() override;

  /// Binds the entries to this frame and the scene, then searches; returns the starting poses
  /// (scene <- robot), best first; empty when an entry is absent or nothing is found it trusts.
  std::vector<Pose> seeds(const Frame& frame, const PropertyContainer& scene,
                          const AlignContext<S>& context);

 protected:
  /// The search, with every entry bound; `context.guess` is the prediction.
  virtual std::vector<Pose> search(const AlignContext<S>& context) = 0;
};

extern template class AlignSeeder<Space2D>;
extern template class AlignSeeder<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
