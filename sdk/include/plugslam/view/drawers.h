#pragma once
// How values held in containers are drawn: a plugin registers, for its cue's value types, a
// function turning a value into a point cloud in the value's own frame (a measurement in the
// robot's frame, a scene entry in its local map's frame). The runtime's viewer stream then shows
// every cue of every frame and every local map without knowing any cue.
#include <functional>
#include <mutex>
#include <string>
#include <typeindex>
#include <vector>

#include "plugslam/property.h"
#include "plugslam/view/drawables.h"

namespace plugslam {
inline namespace abi_v1 {
namespace view {

/// The process-wide table of drawers by value type; thread-safe.
class Drawers {
 public:
  /// Draws one value into `out` (points, colours; the caller sets stamp, frame and pose).
  using Draw = std::function<void(const PropertyBase& value, PointCloud& out)>;

  /// The table.
  static Drawers& instance();

  /// Registers the drawer of T for `owner` (the plugin: removeOwner drops it before unloading).
  /// A second drawer for T replaces the first.
  template <class T>
  void add(const std::string& owner, std::function<void(const T&, PointCloud&)> draw) {
    addEntry(std::type_index(typeid(T)), owner,
             [draw = std::move(draw)](const PropertyBase& p, PointCloud& out) {
               draw(static_cast<const Property<T>&>(p).value(), out);
             });
  }
  /// Registers a type-erased drawer (what add<T> builds).
  void addEntry(std::type_index type, const std::string& owner, Draw draw);
  /// True when values of `type` can be drawn.
  bool canDraw(const std::type_index& type) const;
  /// Draws `value` into `out`; false (and `out` untouched) when its type has no drawer.
  bool draw(const PropertyBase& value, PointCloud& out) const;
  /// Removes the drawers of `owner`; returns how many.
  size_t removeOwner(const std::string& owner);

 private:
  Drawers() = default;
  struct Entry {
    std::type_index type;
    std::string owner;
    Draw draw;
  };
  mutable std::mutex mutex_;
  std::vector<Entry> entries_;
};

}  // namespace view
}  // namespace abi_v1
}  // namespace plugslam
