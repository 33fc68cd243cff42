#include "point_cloud2d.h"

#include <atomic>
#include <string>

#include "plugslam/errors.h"

namespace plugslam {
namespace laser2d {

namespace {
std::atomic<uint64_t> next_revision{1};

// One field list for save and load.
template <class Ar, class C>
void cloudFields(Ar& ar, C& c) {
  ar.beginObject();
  ar.field("points", c.points);
  ar.field("normals", c.normals);
  ar.field("weights", c.weights);
  ar.field("sensor_origin", c.sensor_origin);
  ar.endObject();
}
}  // namespace

void PointCloud2D::clear() {
  points.clear();
  normals.clear();
  weights.clear();
  touch();
}

void PointCloud2D::touch() { revision = next_revision.fetch_add(1, std::memory_order_relaxed); }

void PointCloud2D::checkConsistent() const {
  if (normals.size() != points.size() || weights.size() != points.size())
    throw InputError("PointCloud2D: expected as many normals and weights as points, got " +
                     std::to_string(points.size()) + " points, " + std::to_string(normals.size()) +
                     " normals, " + std::to_string(weights.size()) + " weights");
}

void save(OutArchive& ar, const PointCloud2D& c) { cloudFields(ar, c); }

void load(InArchive& ar, PointCloud2D& c) {
  cloudFields(ar, c);
  if (c.normals.size() != c.points.size() || c.weights.size() != c.points.size())
    ar.fail("PointCloud2D: expected as many normals and weights as points");
  c.touch();
}

}  // namespace laser2d
}  // namespace plugslam
