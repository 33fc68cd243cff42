#pragma once
// AlignerSlice: the part of the Multi-Aligner that handles one cue. It binds a measurement entry
// to a scene entry by name, associates them at the current estimate, and adds its factors on
// the one relative-pose variable to the shared normal equations.
#include <string>

#include "plugslam/configurable.h"
#include "plugslam/frame.h"
#include "plugslam/pose_space.h"

namespace plugslam {
inline namespace abi_v1 {

/// Gauss-Newton normal equations of the aligner's single pose, accumulated over slices.
template <class S>
struct NormalEquations {
  typename S::Matrix H = S::Matrix::Zero();  ///< J^T W J
  typename S::Vector b = S::Vector::Zero();  ///< J^T W e
  double chi2 = 0;                           ///< sum of robustified squared errors
  size_t inliers = 0;                        ///< factors within the kernel's inlier band
  size_t factors = 0;                        ///< factors added
  size_t candidates = 0;  ///< measurement elements the slices tried to associate (overlap base)
  void clear() { *this = NormalEquations(); }
};

/// What a slice knows about the frame being aligned, besides its cue.
template <class S>
struct AlignContext {
  typename S::Pose previous;  ///< the previous frame's pose in the scene frame
  typename S::Pose guess;     ///< the initial estimate (the motion prediction)
};

/// One cue's contribution to the Multi-Aligner.
template <class S>
class AlignerSlice : public Configurable {
 public:
  static constexpr const char* kKind = S::kDim == 2 ? "AlignerSlice2D" : "AlignerSlice3D";
  using Pose = typename S::Pose;
  ~AlignerSlice() override;

  /// Takes this frame's inputs. The scene is the local map (in its own frame). Returns false when
  /// the cue is absent this frame (the slice then adds nothing).
  virtual bool bind(const Frame& frame, const PropertyContainer& scene,
                    const AlignContext<S>& context) = 0;
  /// Data association at estimate T (scene <- robot); called once per outer iteration.
  virtual void associate(const Pose& t) { (void)t; }
  /// Adds the slice's linearised factors at T.
  virtual void linearize(const Pose& t, NormalEquations<S>& eq) const = 0;
  /// True when the slice needs a non-empty scene (false for e.g. an odometry prior).
  virtual bool needsScene() const { return true; }
};

extern template class AlignerSlice<Space2D>;
extern template class AlignerSlice<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
