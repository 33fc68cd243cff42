// The installed publisher and the drawer table.
#include <algorithm>

#include "plugslam/view/drawers.h"
#include "plugslam/view/publisher.h"

namespace plugslam {
inline namespace abi_v1 {
namespace view {

namespace detail {
std::atomic<Publisher*> g_publisher{nullptr};
std::atomic<uint64_t> g_publisher_generation{0};
}  // namespace detail

Publisher::~Publisher() = default;

void installPublisher(Publisher* publisher) {
  // A new generation makes every Channel declare itself again with the new publisher.
  detail::g_publisher_generation.fetch_add(1, std::memory_order_acq_rel);
  detail::g_publisher.store(publisher, std::memory_order_release);
}

Drawers& Drawers::instance() {
  static Drawers drawers;
  return drawers;
}

void Drawers::addEntry(std::type_index type, const std::string& owner, Draw draw) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& e : entries_) {
    if (e.type == type) {
      e.owner = owner;
      e.draw = std::move(draw);
      return;
    }
  }
  entries_.push_back(Entry{type, owner, std::move(draw)});
}

bool Drawers::canDraw(const std::type_index& type) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return std::any_of(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.type == type; });
}

bool Drawers::draw(const PropertyBase& value, PointCloud& out) const {
  Draw draw;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& e : entries_)
      if (e.type == value.type()) draw = e.draw;
  }
  if (!draw) return false;
  draw(value, out);
  return true;
}

size_t Drawers::removeOwner(const std::string& owner) {
  std::lock_guard<std::mutex> lock(mutex_);
  const size_t before = entries_.size();
  entries_.erase(std::remove_if(entries_.begin(), entries_.end(),
                                [&](const Entry& e) { return e.owner == owner; }),
                 entries_.end());
  return before - entries_.size();
}

}  // namespace view
}  // namespace abi_v1
}  // namespace plugslam
