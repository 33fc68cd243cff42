#include "plugslam/sensor_data.h"

#include "plugslam/archive.h"

namespace plugslam {
inline namespace abi_v1 {

void save(OutArchive& ar, const LaserScan& s) {
  ar.beginObject();
  ar.field("stamp", s.stamp);
  ar.field("angle_min", s.angle_min);
  ar.field("angle_increment", s.angle_increment);
  ar.field("range_min", s.range_min);
  ar.field("range_max", s.range_max);
  ar.field("ranges", s.ranges);
  ar.field("mount", s.mount);
  ar.endObject();
}

void load(InArchive& ar, LaserScan& s) {
  ar.beginObject();
  ar.field("stamp", s.stamp);
  ar.field("angle_min", s.angle_min);
  ar.field("angle_increment", s.angle_increment);
  ar.field("range_min", s.range_min);
  ar.field("range_max", s.range_max);
  ar.field("ranges", s.ranges);
  ar.field("mount", s.mount);
  ar.endObject();
}

void save(OutArchive& ar, const Odometry2D& o) {
  ar.beginObject();
  ar.field("stamp", o.stamp);
  ar.field("pose", o.pose);
  ar.endObject();
}

void load(InArchive& ar, Odometry2D& o) {
  ar.beginObject();
  ar.field("stamp", o.stamp);
  ar.field("pose", o.pose);
  ar.endObject();
}

}  // namespace abi_v1
}  // namespace plugslam
