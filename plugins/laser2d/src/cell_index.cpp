#include "cell_index.h"

#include <cmath>

namespace plugslam {
namespace laser2d {

namespace {
uint64_t mix(uint64_t k) {
  k ^= k >> 33;
  k *= 0xff51afd7ed558ccdULL;
  k ^= k >> 33;
  return k;
}
}  // namespace

void CellIndex::reset(double cell, size_t expected) {
  inv_cell_ = 1.0 / cell;
  size_t cap = 64;
  while (cap < 2 * expected) cap *= 2;
  if (keys_.size() < cap) {
    keys_.resize(cap);
    heads_.resize(cap);
  }
  std::fill(heads_.begin(), heads_.end(), -1);
  next_.clear();
  next_.reserve(expected);
  used_ = 0;
}

int64_t CellIndex::find(uint64_t k) const {
  const size_t mask = keys_.size() - 1;
  for (size_t s = mix(k) & mask;; s = (s + 1) & mask) {
    if (heads_[s] < 0) return -1;
    if (keys_[s] == k) return static_cast<int64_t>(s);
  }
}

void CellIndex::grow() {
  std::vector<uint64_t> keys(keys_.size() * 2);
  std::vector<int> heads(keys.size(), -1);
  const size_t mask = keys.size() - 1;
  for (size_t s = 0; s < keys_.size(); ++s) {
    if (heads_[s] < 0) continue;
    size_t t = mix(keys_[s]) & mask;
    while (heads[t] >= 0) t = (t + 1) & mask;
    keys[t] = keys_[s];
    heads[t] = heads_[s];
  }
  keys_.swap(keys);
  heads_.swap(heads);
}

void CellIndex::insert(const Eigen::Vector2d& p, int index) {
  if (2 * (used_ + 1) > keys_.size()) grow();
  if (next_.size() <= static_cast<size_t>(index)) next_.resize(index + 1, -1);
  const uint64_t k = key(cellOf(p.x()), cellOf(p.y()));
  const size_t mask = keys_.size() - 1;
  size_t s = mix(k) & mask;
  while (heads_[s] >= 0 && keys_[s] != k) s = (s + 1) & mask;
  if (heads_[s] < 0) {
    keys_[s] = k;
    ++used_;
  }
  next_[index] = heads_[s];
  heads_[s] = index;
}

}  // namespace laser2d
}  // namespace plugslam
