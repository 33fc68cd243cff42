#include "plugslam/landmarks/landmark_map.h"

#include <algorithm>
#include <atomic>
#include <string>

#include "plugslam/archive.h"
#include "plugslam/errors.h"
#include "properties/base64.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {
std::atomic<uint64_t> next_revision{1};

template <class T>
void keep(std::vector<T>& v, const std::vector<bool>& flags) {
  size_t out = 0;
  for (size_t i = 0; i < v.size(); ++i)
    if (flags[i]) v[out++] = v[i];
  v.resize(out);
}
}  // namespace

void LandmarkMap::push(const Eigen::Vector3d& position, const Eigen::Matrix3d& covariance,
                       uint64_t id, const uint8_t* descriptor, uint32_t colour, uint64_t seq,
                       double reference_distance) {
  positions.push_back(position);
  covariances.push_back(covariance);
  ids.push_back(id);
  observations.push_back(1);
  visible.push_back(1);
  last_seen.push_back(seq);
  colours.push_back(colour);
  reference_distances.push_back(reference_distance);
  descriptors.insert(descriptors.end(), descriptor, descriptor + descriptor_bytes);
}

void LandmarkMap::keepOnly(const std::vector<bool>& flags) {
  if (flags.size() != size())
    throw InputError("LandmarkMap::keepOnly: expected " + std::to_string(size()) + " flags, got " +
                     std::to_string(flags.size()));
  const size_t bytes = static_cast<size_t>(descriptor_bytes);
  size_t out = 0;
  for (size_t i = 0; i < flags.size(); ++i) {
    if (!flags[i]) continue;
    if (out != i)
      std::copy(descriptors.begin() + i * bytes, descriptors.begin() + (i + 1) * bytes,
                descriptors.begin() + out * bytes);
    ++out;
  }
  descriptors.resize(out * bytes);
  keep(positions, flags);
  keep(covariances, flags);
  keep(ids, flags);
  keep(observations, flags);
  keep(visible, flags);
  keep(last_seen, flags);
  keep(colours, flags);
  keep(reference_distances, flags);
  touch();
}

void LandmarkMap::clear() {
  positions.clear();
  covariances.clear();
  ids.clear();
  observations.clear();
  visible.clear();
  last_seen.clear();
  colours.clear();
  reference_distances.clear();
  descriptors.clear();
  touch();
}

void LandmarkMap::touch() { revision = next_revision.fetch_add(1, std::memory_order_relaxed); }

void LandmarkMap::checkConsistent() const {
  const size_t n = size();
  if (covariances.size() != n || ids.size() != n || observations.size() != n ||
      visible.size() != n || last_seen.size() != n || colours.size() != n ||
      reference_distances.size() != n || descriptor_bytes <= 0 || descriptors.size() != n * static_cast<size_t>(descriptor_bytes))
    throw InputError("LandmarkMap: expected every array to hold " + std::to_string(n) +
                     " landmarks (descriptors: " + std::to_string(descriptor_bytes) +
                     " bytes each)");
}

void save(OutArchive& ar, const LandmarkMap& m) {
  m.checkConsistent();
  std::vector<double> cov(9 * m.size());
  for (size_t i = 0; i < m.size(); ++i) Eigen::Map<Eigen::Matrix3d>(cov.data() + 9 * i) = m.covariances[i];
  ar.beginObject();
  ar.field("positions", m.positions).field("covariances", cov).field("ids", m.ids);
  ar.field("observations", m.observations).field("visible", m.visible);
  ar.field("last_seen", m.last_seen).field("colours", m.colours);
  ar.field("reference_distances", m.reference_distances);
  ar.field("descriptor_bytes", m.descriptor_bytes);
  ar.field("descriptors", detail::toBase64(m.descriptors.data(), m.descriptors.size()));
  ar.endObject();
}

void load(InArchive& ar, LandmarkMap& m) {
  ar.beginObject();
  std::vector<double> cov;
  ar.field("positions", m.positions).field("covariances", cov).field("ids", m.ids);
  ar.field("observations", m.observations).field("visible", m.visible);
  ar.field("last_seen", m.last_seen).field("colours", m.colours);
  // Maps saved before the image pyramid have no reference distances (unknown: no scale check).
  const std::vector<std::string> keys = ar.keys();
  if (std::find(keys.begin(), keys.end(), "reference_distances") != keys.end())
    ar.field("reference_distances", m.reference_distances);
  else
    m.reference_distances.assign(m.positions.size(), 0.0);
  ar.field("descriptor_bytes", m.descriptor_bytes);
  std::string text;
  ar.field("descriptors", text);
  if (!detail::fromBase64(text, m.descriptors)) ar.fail("LandmarkMap: descriptors are not base64");
  if (cov.size() != 9 * m.positions.size())
    ar.fail("LandmarkMap: expected 9 covariance values per landmark");
  m.covariances.resize(m.positions.size());
  for (size_t i = 0; i < m.size(); ++i)
    m.covariances[i] = Eigen::Map<const Eigen::Matrix3d>(cov.data() + 9 * i);
  try {
    m.checkConsistent();
  } catch (const InputError& e) {
    ar.fail(e.what());
  }
  ar.endObject();
  m.touch();
}

}  // namespace abi_v1
}  // namespace plugslam
