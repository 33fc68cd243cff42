#include "view/view_json.h"

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "view/jpeg.h"

namespace plugslam::runtime {

using nlohmann::json;

namespace {

// Six decimals: micrometres and micro-radians, far below what a viewer shows, and JSON numbers
// half as long as full doubles.
double round6(double v) { return std::isfinite(v) ? std::round(v * 1e6) / 1e6 : 0.0; }

json time(double seconds) {
  if (!(seconds > 0)) return json{{"sec", 0}, {"nsec", 0}};
  const double whole = std::floor(seconds);
  auto nsec = static_cast<int64_t>(std::llround((seconds - whole) * 1e9));
  auto sec = static_cast<int64_t>(whole);
  if (nsec >= 1000000000) {
    ++sec;
    nsec -= 1000000000;
  }
  return json{{"sec", sec}, {"nsec", nsec}};
}

json vec3(const Eigen::Vector3d& v) {
  return json{{"x", round6(v.x())}, {"y", round6(v.y())}, {"z", round6(v.z())}};
}

json pose(const Eigen::Isometry3d& T) {
  Eigen::Quaterniond q(T.linear());
  q.normalize();
  return json{{"position", vec3(T.translation())},
              {"orientation",
               {{"x", round6(q.x())}, {"y", round6(q.y())}, {"z", round6(q.z())},
                {"w", round6(q.w())}}}};
}

json color(const view::Color& c) { return json{{"r", c.r}, {"g", c.g}, {"b", c.b}, {"a", c.a}}; }

json field(const char* name, int offset, int type) {
  return json{{"name", name}, {"offset", offset}, {"type", type}};
}
constexpr int kUint8 = 1, kFloat32 = 7;

json encode(const view::FrameTransforms& m) {
  json list = json::array();
  for (const auto& t : m.transforms) {
    json p = pose(t.transform);
    list.push_back(json{{"timestamp", time(t.stamp)},
                        {"parent_frame_id", t.parent},
                        {"child_frame_id", t.child},
                        {"translation", p["position"]},
                        {"rotation", p["orientation"]}});
  }
  return json{{"transforms", std::move(list)}};
}

json encode(const view::PoseInFrame& m) {
  return json{{"timestamp", time(m.stamp)}, {"frame_id", m.frame}, {"pose", pose(m.pose)}};
}

json encode(const view::PosesInFrame& m) {
  json poses = json::array();
  for (const auto& p : m.poses) poses.push_back(pose(p));
  return json{{"timestamp", time(m.stamp)}, {"frame_id", m.frame}, {"poses", std::move(poses)}};
}

json encode(const view::PointCloud& m) {
  const bool colored = !m.colors.empty() && m.colors.size() == m.points.size();
  const size_t stride = colored ? 16 : 12;
  std::string data(m.points.size() * stride, '\0');
  for (size_t i = 0; i < m.points.size(); ++i) {
    // Little-endian float32, as PackedElementField says (every target of this host is).
    std::memcpy(&data[i * stride], m.points[i].data(), 12);
    if (colored) std::memcpy(&data[i * stride + 12], m.colors[i].data(), 4);
  }
  json fields = json::array({field("x", 0, kFloat32), field("y", 4, kFloat32),
                             field("z", 8, kFloat32)});
  if (colored) {
    fields.push_back(field("red", 12, kUint8));
    fields.push_back(field("green", 13, kUint8));
    fields.push_back(field("blue", 14, kUint8));
    fields.push_back(field("alpha", 15, kUint8));
  }
  return json{{"timestamp", time(m.stamp)}, {"frame_id", m.frame},
              {"pose", pose(m.pose)},        {"point_stride", stride},
              {"fields", std::move(fields)}, {"data", base64(data.data(), data.size())}};
}

json encode(const view::Grid& m) {
  return json{{"timestamp", time(m.stamp)},
              {"frame_id", m.frame},
              {"pose", pose(m.pose)},
              {"column_count", m.width},
              {"cell_size", {{"x", m.cell_size}, {"y", m.cell_size}}},
              {"row_stride", m.width},
              {"cell_stride", 1},
              {"fields", json::array({field("occupancy", 0, kUint8)})},
              {"data", base64(m.cells.data(), m.cells.size())}};
}

json encode(const view::SceneUpdate& m) {
  json deletions = json::array();
  for (const auto& id : m.deleted)
    deletions.push_back(json{{"timestamp", time(m.stamp)}, {"type", 0}, {"id", id}});
  json entities = json::array();
  for (const auto& e : m.entities) {
    json lines = json::array();
    for (const auto& l : e.lines) {
      json points = json::array();
      for (const auto& p : l.points) points.push_back(vec3(p));
      lines.push_back(json{{"type", static_cast<int>(l.type)},
                           {"pose", pose(Eigen::Isometry3d::Identity())},
                           {"thickness", l.thickness},
                           {"scale_invariant", l.scale_invariant},
                           {"points", std::move(points)},
                           {"color", color(l.color)},
                           {"colors", json::array()},
                           {"indices", json::array()}});
    }
    entities.push_back(json{{"timestamp", time(e.stamp)},
                            {"frame_id", e.frame},
                            {"id", e.id},
                            {"lifetime", {{"sec", 0}, {"nsec", 0}}},
                            {"frame_locked", true},
                            {"metadata", json::array()},
                            {"arrows", json::array()},
                            {"cubes", json::array()},
                            {"spheres", json::array()},
                            {"cylinders", json::array()},
                            {"lines", std::move(lines)},
                            {"triangles", json::array()},
                            {"texts", json::array()},
                            {"models", json::array()}});
  }
  return json{{"deletions", std::move(deletions)}, {"entities", std::move(entities)}};
}

json encode(const view::CameraImage& m) {
  const std::string jpeg = encodeJpeg(m.image);
  return json{{"timestamp", time(m.image.stamp)},
              {"frame_id", m.frame},
              {"data", base64(jpeg.data(), jpeg.size())},
              {"format", "jpeg"}};
}

// The camera's lens model as foxglove.CameraCalibration names it, with the coefficient count its
// schema documents (plumb_bob 5, rational_polynomial 8, kannala_brandt 4). OpenCV's thin-prism and
// tilt terms (12 or 14 coefficients) have no Foxglove model: the first 8 are sent.
std::pair<const char*, json> distortion(const Distortion& d) {
  auto first = [&d](size_t n) {
    json out = json::array();
    for (size_t i = 0; i < n; ++i) out.push_back(i < d.coefficients.size() ? d.coefficients[i] : 0.0);
    return out;
  };
  switch (d.model) {
    case Distortion::Model::kRadialTangential:
      if (d.coefficients.size() > 5) return {"rational_polynomial", first(8)};
      return {"plumb_bob", first(5)};
    case Distortion::Model::kEquidistant:
      return {"kannala_brandt", first(4)};
    case Distortion::Model::kNone:
      break;
  }
  return {"plumb_bob", first(5)};  // all zero: an ideal pinhole
}

json encode(const view::CameraCalibration& m) {
  const CameraInfo& c = m.info;
  auto [model, coefficients] = distortion(c.distortion);
  return json{{"timestamp", time(m.stamp)},
              {"frame_id", m.frame},
              {"width", c.width},
              {"height", c.height},
              {"distortion_model", model},
              {"D", std::move(coefficients)},
              {"K", {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1}},
              {"R", {1, 0, 0, 0, 1, 0, 0, 0, 1}},
              {"P", {c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0}}};  // the left (or only) camera: no baseline term
}

json encode(const view::Status& m) {
  return json{{"timestamp", time(m.stamp)},
              {"frame", m.frame},
              {"total_frames", m.total},
              {"hz", round6(m.hz)},
              {"loops", m.loops},
              {"local_maps", m.local_maps},
              {"tracking_failures", m.tracking_failures},
              {"state", m.state},
              {"run", m.run}};
}

json encode(const view::LogLine& m) {
  return json{{"timestamp", time(m.stamp)}, {"level", static_cast<int>(m.level)},
              {"message", m.message},       {"name", m.name},
              {"file", ""},                 {"line", 0}};
}

// Small helpers for the advertised schemas.
json num() { return json{{"type", "number"}}; }
json integer() { return json{{"type", "integer"}}; }
json str() { return json{{"type", "string"}}; }
json obj(json properties) {
  json required = json::array();
  for (auto it = properties.begin(); it != properties.end(); ++it) required.push_back(it.key());
  return json{{"type", "object"}, {"properties", std::move(properties)}, {"required", required}};
}
json arr(json items) { return json{{"type", "array"}, {"items", std::move(items)}}; }
json timeSchema() { return obj({{"sec", integer()}, {"nsec", integer()}}); }
json vec3Schema() { return obj({{"x", num()}, {"y", num()}, {"z", num()}}); }
json quatSchema() { return obj({{"x", num()}, {"y", num()}, {"z", num()}, {"w", num()}}); }
json poseSchema() { return obj({{"position", vec3Schema()}, {"orientation", quatSchema()}}); }
json bytesSchema() { return json{{"type", "string"}, {"contentEncoding", "base64"}}; }
json fieldsSchema() { return arr(obj({{"name", str()}, {"offset", integer()}, {"type", integer()}})); }
json colorSchema() { return obj({{"r", num()}, {"g", num()}, {"b", num()}, {"a", num()}}); }

json schemaOf(size_t kind) {
  switch (kind) {
    case view::kindOf<view::FrameTransforms>():
      return obj({{"transforms", arr(obj({{"timestamp", timeSchema()},
                                          {"parent_frame_id", str()},
                                          {"child_frame_id", str()},
                                          {"translation", vec3Schema()},
                                          {"rotation", quatSchema()}}))}});
    case view::kindOf<view::PoseInFrame>():
      return obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"pose", poseSchema()}});
    case view::kindOf<view::PosesInFrame>():
      return obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"poses", arr(poseSchema())}});
    case view::kindOf<view::PointCloud>():
      return obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"pose", poseSchema()},
                  {"point_stride", integer()}, {"fields", fieldsSchema()},
                  {"data", bytesSchema()}});
    case view::kindOf<view::Grid>():
      return obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"pose", poseSchema()},
                  {"column_count", integer()}, {"cell_size", obj({{"x", num()}, {"y", num()}})},
                  {"row_stride", integer()}, {"cell_stride", integer()},
                  {"fields", fieldsSchema()}, {"data", bytesSchema()}});
    case view::kindOf<view::SceneUpdate>(): {
      json line = obj({{"type", integer()}, {"pose", poseSchema()}, {"thickness", num()},
                       {"scale_invariant", json{{"type", "boolean"}}},
                       {"points", arr(vec3Schema())}, {"color", colorSchema()},
                       {"colors", arr(colorSchema())}, {"indices", arr(integer())}});
      json entity = obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"id", str()},
                         {"lifetime", timeSchema()}, {"frame_locked", json{{"type", "boolean"}}},
                         {"lines", arr(line)}});
      return obj({{"deletions", arr(obj({{"timestamp", timeSchema()}, {"type", integer()},
                                         {"id", str()}}))},
                  {"entities", arr(entity)}});
    }
    case view::kindOf<view::CameraImage>():
      return obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"data", bytesSchema()},
                  {"format", str()}});
    case view::kindOf<view::CameraCalibration>():
      return obj({{"timestamp", timeSchema()}, {"frame_id", str()}, {"width", integer()},
                  {"height", integer()}, {"distortion_model", str()}, {"D", arr(num())},
                  {"K", arr(num())}, {"R", arr(num())}, {"P", arr(num())}});
    case view::kindOf<view::Status>():
      return obj({{"timestamp", timeSchema()}, {"frame", integer()}, {"total_frames", integer()},
                  {"hz", num()}, {"loops", integer()}, {"local_maps", integer()},
                  {"tracking_failures", integer()}, {"state", str()}, {"run", integer()}});
    case view::kindOf<view::LogLine>():
      return obj({{"timestamp", timeSchema()}, {"level", integer()}, {"message", str()},
                  {"name", str()}, {"file", str()}, {"line", integer()}});
  }
  return json::object();
}

}  // namespace

std::string schemaName(size_t kind) {
  static const char* const names[] = {
      "foxglove.FrameTransforms", "foxglove.PoseInFrame",      "foxglove.PosesInFrame",
      "foxglove.PointCloud",      "foxglove.Grid",             "foxglove.SceneUpdate",
      "foxglove.CompressedImage", "foxglove.CameraCalibration", "plugslam.Status",
      "foxglove.Log"};
  static_assert(sizeof(names) / sizeof(names[0]) == std::variant_size_v<view::Drawable>,
                "one schema name per drawable");
  return kind < std::variant_size_v<view::Drawable> ? names[kind] : "";
}

std::string jsonSchema(size_t kind) {
  json s = schemaOf(kind);
  s["title"] = schemaName(kind);
  return s.dump();
}

std::string encodeJson(const view::Drawable& drawable) {
  return std::visit([](const auto& m) { return encode(m).dump(); }, drawable);
}

std::string base64(const void* data, size_t size) {
  static const char* const alphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const uint8_t*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const uint32_t v = (p[i] << 16) | (p[i + 1] << 8) | p[i + 2];
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += alphabet[(v >> 6) & 63];
    out += alphabet[v & 63];
  }
  if (i < size) {
    uint32_t v = p[i] << 16;
    if (i + 1 < size) v |= p[i + 1] << 8;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += i + 1 < size ? alphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

}  // namespace plugslam::runtime
