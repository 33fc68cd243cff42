// The tracker interfaces' out-of-line parts: destructors (they anchor the vtables in the SDK),
// the defaults of Tracker's optional abilities, and the slice and motion-model instantiations.
#include "plugslam/tracker.h"

#include "plugslam/errors.h"
#include "plugslam/motion_model.h"
#include "plugslam/tracker_slice.h"

namespace plugslam {
inline namespace abi_v1 {

Tracker::~Tracker() = default;

void Tracker::continueSession(int64_t) {
  throw InputError("tracker '" + name() + "' (" + typeName() + ") cannot extend a saved session");
}

void Tracker::relocate(const Eigen::Isometry3d&) {
  throw InputError("tracker '" + name() + "' (" + typeName() + ") cannot be relocated");
}

std::shared_ptr<Tracker> Tracker::localizer(std::vector<std::shared_ptr<const LocalMap>>) const {
  throw InputError("tracker '" + name() + "' (" + typeName() + ") cannot localize in saved maps");
}

template <class S>
TrackerSlice<S>::~TrackerSlice() = default;

template <class S>
void TrackerSlice<S>::merge(const Frame& frame, PropertyContainer& scene, const Pose& t) {
  bool present = true;
  for (EntryBase* entry : entries()) {
    if (entry->writes()) {
      if (entry->container() != Container::scene)
        throw InputError("tracker slice '" + name() + "': '" + entry->key() + "' " +
                         entry->describe() + "; a tracker slice writes scene entries only");
      entry->bind(&scene);
      continue;
    }
    const Container c = entry->container();
    entry->bind(static_cast<const PropertyContainer*>(c == Container::scene ? &scene
                                                      : c == Container::raw ? &frame.raw
                                                                            : &frame.measurement));
    present = present && entry->bound();
  }
  if (present) integrate(MergeContext<S>{t, frame.seq, frame.stamp});
}
template <class S>
MotionModel<S>::~MotionModel() = default;

Param<double> maxAccelerationParam(Configurable* owner, std::string doc) {
  return {owner,   "max_acceleration", ConstantVelocityBounds{}.acceleration,
          "m/s^2", std::move(doc),     Range{0, 1e4}};
}

Param<double> maxAngularAccelerationParam(Configurable* owner, std::string doc) {
  return {owner,
          "max_angular_acceleration",
          ConstantVelocityBounds{}.angular_acceleration,
          "rad/s^2",
          std::move(doc),
          Range{0, 1e4}};
}

ConstantVelocityBounds constantVelocityBounds(double max_acceleration,
                                              double max_angular_acceleration) {
  ConstantVelocityBounds b;
  b.acceleration = max_acceleration;
  b.angular_acceleration = max_angular_acceleration;
  return b;
}

template <class S>
HandoverSlice<S>::~HandoverSlice() = default;
template <class S>
RefiningSlice<S>::~RefiningSlice() = default;

template class TrackerSlice<Space2D>;
template class TrackerSlice<Space3D>;
template class HandoverSlice<Space2D>;
template class HandoverSlice<Space3D>;
template class RefiningSlice<Space2D>;
template class RefiningSlice<Space3D>;
template class MotionModel<Space2D>;
template class MotionModel<Space3D>;

}  // namespace abi_v1
}  // namespace plugslam
