#include "plugslam/statistics.h"

#include "plugslam/configurable.h"

namespace plugslam {
inline namespace abi_v1 {

StatisticsSource::~StatisticsSource() = default;

namespace {
void collect(const Configurable& m,
             std::vector<std::pair<std::string, std::vector<Statistic>>>& out) {
  if (const auto* s = dynamic_cast<const StatisticsSource*>(&m)) {
    auto figures = s->statistics();
    if (!figures.empty()) out.emplace_back(m.name(), std::move(figures));
  }
  for (const SlotBase* slot : m.slots())
    for (const auto& item : slot->items())
      if (item) collect(*item, out);
}
}  // namespace

std::vector<std::pair<std::string, std::vector<Statistic>>> collectStatistics(
    const Configurable& root) {
  std::vector<std::pair<std::string, std::vector<Statistic>>> out;
  collect(root, out);
  return out;
}

}  // namespace abi_v1
}  // namespace plugslam
