#include "plugslam/landmarks/appearance_detector.h"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>

#include "plugslam/errors.h"
#include "plugslam/landmarks/feature_set.h"
#include "plugslam/landmarks/landmark_map.h"

namespace plugslam {
inline namespace abi_v1 {

// An HBST-style binary search tree over descriptors: each inner node tests one bit, chosen when
// its leaf overflowed as the bit that splits that leaf's descriptors most evenly, so similar
// descriptors share a path. A query descends to one leaf and compares only against it: matches
// that differ in a tested bit are missed, which costs recall evenly over all maps and so leaves
// the vote ranking intact, and the search stays logarithmic in the index size.
struct AppearanceDetector::Index {
  struct Node {
    int bit = -1;          // tested bit; -1 for a leaf
    int child[2] = {-1, -1};
    int depth = 0;
    std::vector<uint32_t> entries;  // leaf only
    size_t retry_at = 0;            // a leaf that found no splitting bit retries at this size
  };

  int bytes = -1;  // descriptor size, fixed by the first map indexed
  std::vector<uint8_t> pool;
  std::vector<int64_t> owner;  // map id of each entry
  std::vector<Node> nodes{Node{}};
  std::vector<char> indexed;  // by map id
  std::mutex mutex;           // detect() may run on the back-end thread

  const uint8_t* descriptor(uint32_t e) const {
    return pool.data() + static_cast<size_t>(e) * static_cast<size_t>(bytes);
  }
  static int bitOf(const uint8_t* d, int bit) { return (d[bit >> 3] >> (bit & 7)) & 1; }

  int leafOf(const uint8_t* d) const {
    int n = 0;
    while (nodes[static_cast<size_t>(n)].bit >= 0) {
      const Node& node = nodes[static_cast<size_t>(n)];
      n = node.child[bitOf(d, node.bit)];
    }
    return n;
  }

  void split(int n, int leaf_size, int max_depth) {
    Node& leaf = nodes[static_cast<size_t>(n)];
    if (static_cast<int>(leaf.entries.size()) <= leaf_size || leaf.depth >= max_depth ||
        leaf.entries.size() < leaf.retry_at)
      return;
    const int bits = bytes * 8;
    std::vector<int> ones(static_cast<size_t>(bits), 0);
    for (uint32_t e : leaf.entries) {
      const uint8_t* d = descriptor(e);
      for (int b = 0; b < bits; ++b) ones[static_cast<size_t>(b)] += bitOf(d, b);
    }
    const double half = 0.5 * static_cast<double>(leaf.entries.size());
    int best = -1;
    double best_gap = half;  // a bit all entries share (gap == half) cannot split
    for (int b = 0; b < bits; ++b) {
      const double gap = std::abs(ones[static_cast<size_t>(b)] - half);
      if (gap < best_gap) {
        best_gap = gap;
        best = b;
      }
    }
    if (best < 0) {  // identical descriptors: wait until the leaf doubles
      leaf.retry_at = 2 * leaf.entries.size();
      return;
    }
    Node zero, one;
    zero.depth = one.depth = leaf.depth + 1;
    for (uint32_t e : leaf.entries) (bitOf(descriptor(e), best) ? one : zero).entries.push_back(e);
    leaf.entries.clear();
    leaf.entries.shrink_to_fit();
    leaf.bit = best;
    leaf.child[0] = static_cast<int>(nodes.size());
    leaf.child[1] = static_cast<int>(nodes.size() + 1);
    nodes.push_back(std::move(zero));  // `leaf` is invalid from here
    nodes.push_back(std::move(one));
    split(static_cast<int>(nodes.size() - 2), leaf_size, max_depth);
    split(static_cast<int>(nodes.size() - 1), leaf_size, max_depth);
  }

  void insert(const uint8_t* d, int64_t map, int leaf_size, int max_depth) {
    const auto e = static_cast<uint32_t>(owner.size());
    pool.insert(pool.end(), d, d + bytes);
    owner.push_back(map);
    const int n = leafOf(d);
    nodes[static_cast<size_t>(n)].entries.push_back(e);
    split(n, leaf_size, max_depth);
  }
};

namespace {

const LandmarkMap* landmarksOf(const LocalMap& map, const std::string& entry) {
  return map.scene.find<LandmarkMap>(entry);
}

bool usable(const LandmarkMap& m, size_t i, int min_observations) {
  return m.observations[i] >= static_cast<uint32_t>(min_observations);
}

}  // namespace

AppearanceDetector::AppearanceDetector() : index_(std::make_unique<Index>()) {}
AppearanceDetector::~AppearanceDetector() = default;

void AppearanceDetector::configure() { index_ = std::make_unique<Index>(); }

std::vector<LoopCandidate> AppearanceDetector::detect(const GraphView& view,
                                                      const LocalMap& query) {
  Index& index = *index_;
  std::lock_guard<std::mutex> lock(index.mutex);
  const auto add = [&](const LocalMap& map) {
    if (index.indexed.size() <= static_cast<size_t>(map.id))
      index.indexed.resize(static_cast<size_t>(map.id) + 1, 0);
    if (index.indexed[static_cast<size_t>(map.id)]) return;
    index.indexed[static_cast<size_t>(map.id)] = 1;
    const LandmarkMap* lm = landmarksOf(map, scene());
    if (lm == nullptr || lm->empty()) return;
    if (index.bytes < 0) index.bytes = lm->descriptor_bytes;
    if (lm->descriptor_bytes != index.bytes)
      throw InputError("sdk.AppearanceDetector: local map " + std::to_string(map.id) + " has " +
                       std::to_string(lm->descriptor_bytes) + "-byte descriptors, the index " +
                       std::to_string(index.bytes) + "-byte ones (one descriptor type per run)");
    for (size_t i = 0; i < lm->size(); ++i)
      if (usable(*lm, i, min_observations()))
        index.insert(lm->descriptor(i), map.id, leaf_size(), max_depth());
  };
  for (const auto& map : view.maps)
    if (map && map->id < query.id) add(*map);

  std::vector<LoopCandidate> out;
  const LandmarkMap* lm = landmarksOf(query, scene());
  if (lm != nullptr && !lm->empty() && index.bytes == lm->descriptor_bytes && !index.owner.empty()) {
    // Votes: each query landmark votes once for every map holding a descriptor within
    // max_distance in its leaf (the raw votes gate a candidate), and its vote weighs 1 / the
    // number of maps it matched (what ranks them). A corner of a repeated texture (bricks,
    // windows) matches many maps and so says little about which is the same place; a revisit's
    // own corners match it and its few neighbours.
    std::vector<int> votes(view.maps.size(), 0);
    std::vector<double> weight(view.maps.size(), 0.0);
    std::vector<int64_t> voted_by(view.maps.size(), -1);
    std::vector<size_t> matched;
    size_t used = 0;
    for (size_t i = 0; i < lm->size(); ++i) {
      if (!usable(*lm, i, min_observations())) continue;
      ++used;
      const uint8_t* d = lm->descriptor(i);
      matched.clear();
      for (uint32_t e : index.nodes[static_cast<size_t>(index.leafOf(d))].entries) {
        const auto map = static_cast<size_t>(index.owner[e]);
        if (map >= votes.size() || voted_by[map] == static_cast<int64_t>(i)) continue;
        if (hammingDistance(d, index.descriptor(e), index.bytes) > max_distance()) continue;
        voted_by[map] = static_cast<int64_t>(i);
        matched.push_back(map);
      }
      for (size_t map : matched) {
        ++votes[map];
        weight[map] += 1.0 / static_cast<double>(matched.size());
      }
    }
    const double here = view.travelled[static_cast<size_t>(query.id)];
    std::vector<std::pair<double, int64_t>> ranked;
    for (size_t id = 0; id < votes.size(); ++id) {
      if (static_cast<int64_t>(id) == query.id || votes[id] < min_matches()) continue;
      if (static_cast<double>(votes[id]) < min_ratio() * static_cast<double>(used)) continue;
      // Maps of another component (a session, a run started elsewhere) are never neighbours.
      if (view.component(static_cast<int64_t>(id)) == view.component(query.id) &&
          std::abs(here - view.travelled[id]) < min_travel())
        continue;
      ranked.emplace_back(weight[id], static_cast<int64_t>(id));
    }
    std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first > b.first : a.second < b.second;
    });
    // Place recognition in another component: the estimate says nothing there, so only a place
    // whose votes stand out is trusted. A repeated texture (a street of alike facades, floor
    // tiles) draws as many votes to another stretch of that component as to the best one.
    const int own = view.component(query.id);
    std::vector<int> checked, ambiguous;
    for (const auto& [w, best] : ranked) {
      const int other = view.component(best);
      if (other == own || std::find(checked.begin(), checked.end(), other) != checked.end())
        continue;
      checked.push_back(other);  // its best-voted map comes first
      double elsewhere = 0;
      for (size_t id = 0; id < weight.size(); ++id)
        if (view.component(static_cast<int64_t>(id)) == other &&
            std::abs(view.travelled[id] - view.travelled[static_cast<size_t>(best)]) >=
                min_travel())
          elsewhere = std::max(elsewhere, weight[id]);
      if (elsewhere * (1 + place_margin()) > w) ambiguous.push_back(other);
    }
    ranked.erase(std::remove_if(ranked.begin(), ranked.end(),
                                [&](const auto& r) {
                                  return std::find(ambiguous.begin(), ambiguous.end(),
                                                   view.component(r.second)) != ambiguous.end();
                                }),
                 ranked.end());
    if (ranked.size() > static_cast<size_t>(max_candidates()))
      ranked.resize(static_cast<size_t>(max_candidates()));
    for (const auto& [v, id] : ranked) {
      LoopCandidate c;
      c.id = id;
      c.score = static_cast<double>(v) / static_cast<double>(std::max<size_t>(used, 1));
      // Found by the descriptors alone, whatever the estimate: place recognition.
      c.global = true;
      out.push_back(c);
    }
  }
  // A localizing robot's query is the map it is still building: indexed once it closes.
  if (!view.localizing) add(query);
  return out;
}

}  // namespace abi_v1
}  // namespace plugslam
