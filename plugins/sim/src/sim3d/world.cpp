#include "sim3d/world.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "plugslam/errors.h"
#include "sim2d/random.h"

namespace plugslam {
namespace sim {
namespace sim3d {
namespace {

// Slack on the inside test, so a ray through an edge shared by two faces hits at least one.
constexpr double kEdgeSlack = 1e-9;

uint32_t faceSeed(uint32_t seed, int index) {
  uint32_t h = seed ^ (0x9E3779B9u * static_cast<uint32_t>(index + 1));
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  return h;
}

// Ray-box slab test: true if the ray enters the box before max_t.
bool hitsBox(const Eigen::AlignedBox3d& b, const Eigen::Vector3d& o, const Eigen::Vector3d& inv_d,
             double max_t) {
  double t0 = 0.0, t1 = max_t;
  for (int k = 0; k < 3; ++k) {
    double ta = (b.min()[k] - o[k]) * inv_d[k];
    double tb = (b.max()[k] - o[k]) * inv_d[k];
    if (std::isnan(ta) || std::isnan(tb)) {  // ray parallel to and inside the slab's plane
      if (o[k] < b.min()[k] || o[k] > b.max()[k]) return false;
      continue;
    }
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

Material mat(Pattern p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double scale,
             uint32_t seed) {
  Material m;
  m.pattern = p;
  m.color_a = a;
  m.color_b = b;
  m.scale = scale;
  m.seed = seed;
  return m;
}

Eigen::Isometry3d at(double x, double y, double z, double yaw = 0.0) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

}  // namespace

int World::beginObject(const std::string& name) {
  Object o;
  o.name = name;
  o.first_face = static_cast<int>(faces_.size());
  objects_.push_back(o);
  return static_cast<int>(objects_.size()) - 1;
}

void World::pushFace(Face f) {
  f.object = static_cast<int>(objects_.size()) - 1;
  Object& o = objects_.back();
  for (double s : {0.0, f.width})
    for (double t : {0.0, f.height}) {
      const Eigen::Vector3d c = f.origin + s * f.u + t * f.v;
      o.bounds.extend(c);
      bounds_.extend(c);
    }
  ++o.face_count;
  faces_.push_back(std::move(f));
}

void World::addQuad(const Eigen::Vector3d& origin, const Eigen::Vector3d& u_dir,
                    const Eigen::Vector3d& v_dir, double width, double height,
                    const Material& material, const std::string& name, bool two_sided) {
  if (!(width > 0.0) || !(height > 0.0) || !std::isfinite(width) || !std::isfinite(height))
    throw InputError("sim3d world: quad '" + name + "' needs a positive finite width and height");
  if (!(material.scale > 0.0)) throw InputError("sim3d world: material scale must be positive");
  Face f;
  f.u = u_dir.normalized();
  f.v = (v_dir - v_dir.dot(f.u) * f.u);
  if (!(f.u.allFinite()) || !(f.v.norm() > 1e-12))
    throw InputError("sim3d world: quad '" + name + "' needs two independent edge directions");
  f.v.normalize();
  f.normal = f.u.cross(f.v);
  f.origin = origin;
  f.width = width;
  f.height = height;
  f.two_sided = two_sided;
  f.material = material;
  beginObject(name);
  pushFace(std::move(f));
}

void World::addBox(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size,
                   const Material& material, const std::string& name, bool with_bottom) {
  if (!(size.minCoeff() > 0.0) || !size.allFinite())
    throw InputError("sim3d world: box '" + name + "' needs positive finite sizes");
  if (!(material.scale > 0.0)) throw InputError("sim3d world: material scale must be positive");
  beginObject(name);
  const Eigen::Matrix3d R = pose.linear();
  const Eigen::Vector3d h = 0.5 * size;
  // For each axis k and sign, a face whose normal is sign * e_k, with u x v = normal.
  int index = 0;
  for (int k = 0; k < 3; ++k) {
    for (int sign : {+1, -1}) {
      if (!with_bottom && k == 2 && sign < 0) continue;
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      Eigen::Vector3d n = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::Zero(),
                      v = Eigen::Vector3d::Zero();
      n[k] = sign;
      u[a] = 1.0;
      v[b] = sign;  // flips the winding on the negative side so u x v points outward
      Eigen::Vector3d corner = -h;  // local corner where (s, t) = (0, 0)
      corner[k] = sign * h[k];
      if (sign < 0) corner[b] = h[b];
      Face f;
      f.origin = pose * corner;
      f.u = R * u;
      f.v = R * v;
      f.normal = R * n;
      f.width = size[a];
      f.height = size[b];
      f.two_sided = false;
      f.material = material;
      f.material.seed = faceSeed(material.seed, index++);
      pushFace(std::move(f));
    }
  }
}

bool World::castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                    double max_range, RayHit* hit, double min_range) const {
  const Eigen::Vector3d inv = direction.cwiseInverse();
  double best = max_range;
  int best_face = -1;
  for (const Object& o : objects_) {
    if (!hitsBox(o.bounds, origin, inv, best)) continue;
    for (int i = o.first_face; i < o.first_face + o.face_count; ++i) {
      const Face& f = faces_[i];
      const double nd = f.normal.dot(direction);
      if (nd == 0.0 || (!f.two_sided && nd > 0.0)) continue;
      const double t = f.normal.dot(f.origin - origin) / nd;
      if (!(t > min_range) || !(t <= best)) continue;
      const Eigen::Vector3d q = origin + t * direction - f.origin;
      const double s = f.u.dot(q), tt = f.v.dot(q);
      if (s < -kEdgeSlack || s > f.width + kEdgeSlack || tt < -kEdgeSlack ||
          tt > f.height + kEdgeSlack)
        continue;
      if (t < best || best_face < 0) {
        best = t;
        best_face = i;
      }
    }
  }
  if (best_face < 0) return false;
  if (hit) {
    hit->distance = best;
    hit->face = best_face;
    hit->point = origin + best * direction;
  }
  return true;
}

std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> World::slice(double height) const {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> out;
  for (const Face& f : faces_) {
    // The face's corners; the cut is where the polygon's edges cross z = height.
    const Eigen::Vector3d c[4] = {f.origin, f.origin + f.width * f.u,
                                  f.origin + f.width * f.u + f.height * f.v,
                                  f.origin + f.height * f.v};
    std::vector<Eigen::Vector2d> pts;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d& p = c[k];
      const Eigen::Vector3d& q = c[(k + 1) % 4];
      const double dp = p.z() - height, dq = q.z() - height;
      if ((dp < 0.0) == (dq < 0.0)) continue;
      const double a = dp / (dp - dq);
      pts.push_back((p + a * (q - p)).head<2>());
    }
    if (pts.size() == 2 && (pts[0] - pts[1]).norm() > 1e-9) out.emplace_back(pts[0], pts[1]);
  }
  return out;
}

World World::livingRoom(uint64_t seed) {
  World w;
  const uint32_t s = static_cast<uint32_t>(seed * 0x9E3779B1u);
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                        Z = Eigen::Vector3d::UnitZ();
  const double L = 8.0, W = 6.0, H = 2.7;
  auto c = [](double r, double g, double b) { return Eigen::Vector3d(r, g, b); };
  // Shell: floor, ceiling, four walls, all one-sided with normals (u x v) into the room.
  w.addQuad({0, 0, 0}, X, Y, L, W,
            mat(Pattern::kPlanks, c(0.62, 0.42, 0.25), c(0.30, 0.18, 0.10), 1.0, s + 1), "floor",
            false);
  w.addQuad({0, W, H}, X, -Y, L, W,
            mat(Pattern::kTiles, c(0.92, 0.92, 0.88), c(0.55, 0.55, 0.55), 0.6, s + 2), "ceiling",
            false);
  w.addQuad({L, 0, 0}, -X, Z, L, H,
            mat(Pattern::kBricks, c(0.65, 0.30, 0.22), c(0.80, 0.78, 0.72), 0.3, s + 3),
            "wall_south", false);
  w.addQuad({0, W, 0}, X, Z, L, H,
            mat(Pattern::kNoise, c(0.85, 0.82, 0.70), c(0.55, 0.62, 0.70), 0.35, s + 4),
            "wall_north", false);
  w.addQuad({0, 0, 0}, Y, Z, W, H,
            mat(Pattern::kChecker, c(0.80, 0.75, 0.55), c(0.55, 0.45, 0.35), 0.4, s + 5),
            "wall_west", false);
  w.addQuad({L, W, 0}, -Y, Z, W, H,
            mat(Pattern::kNoise, c(0.75, 0.85, 0.80), c(0.35, 0.50, 0.45), 0.35, s + 6),
            "wall_east", false);
  // Things on the walls, 1 cm in front of them.
  w.addQuad({3.3, W - 0.01, 0.9}, X, Z, 2.2, 1.4,
            mat(Pattern::kWindows, c(0.95, 0.95, 0.95), c(0.25, 0.40, 0.60), 0.55, s + 7), "window",
            false);
  w.addQuad({L - 0.01, 4.9, 0.0}, -Y, Z, 1.0, 2.1,
            mat(Pattern::kPlanks, c(0.55, 0.35, 0.20), c(0.25, 0.15, 0.08), 0.5, s + 8), "door",
            false);
  w.addQuad({4.4, 0.01, 1.3}, -X, Z, 1.2, 0.8,
            mat(Pattern::kPoster, c(1, 1, 1), c(0, 0, 0), 0.2, s + 9), "picture_south", false);
  w.addQuad({0.01, 3.7, 1.2}, Y, Z, 0.9, 0.7,
            mat(Pattern::kPoster, c(1, 1, 1), c(0, 0, 0), 0.15, s + 10), "picture_west", false);
  w.addQuad({2.4, W - 0.01, 1.1}, X, Z, 1.0, 1.0,
            mat(Pattern::kChecker, c(0.95, 0.95, 0.95), c(0.05, 0.05, 0.05), 0.125, s + 11),
            "chart_north", false);
  w.addQuad({L - 0.01, 2.5, 1.0}, -Y, Z, 1.5, 1.0,
            mat(Pattern::kPoster, c(1, 1, 1), c(0, 0, 0), 0.25, s + 12), "picture_east", false);
  w.addQuad({1.3, 3.0, 0.005}, X, Y, 2.6, 1.8,
            mat(Pattern::kTiles, c(0.70, 0.20, 0.20), c(0.90, 0.85, 0.60), 0.3, s + 13), "rug",
            false);
  // Sofa against the north wall.
  const Material fabric =
      mat(Pattern::kNoise, c(0.25, 0.35, 0.55), c(0.15, 0.20, 0.35), 0.25, s + 20);
  w.addBox(at(1.6, 5.3, 0.225), {2.2, 0.9, 0.45}, fabric, "sofa_seat", false);
  w.addBox(at(1.6, 5.65, 0.675), {2.2, 0.2, 0.45}, fabric, "sofa_back", false);
  w.addBox(at(0.4, 5.3, 0.3), {0.2, 0.9, 0.6}, fabric, "sofa_arm_left", false);
  w.addBox(at(2.8, 5.3, 0.3), {0.2, 0.9, 0.6}, fabric, "sofa_arm_right", false);
  w.addBox(at(1.2, 5.05, 0.55), {0.45, 0.15, 0.4},
           mat(Pattern::kChecker, c(0.9, 0.8, 0.2), c(0.8, 0.3, 0.1), 0.1, s + 21), "cushion",
           true);
  // Coffee table with legs.
  const Material wood =
      mat(Pattern::kPlanks, c(0.50, 0.32, 0.18), c(0.28, 0.16, 0.08), 0.8, s + 30);
  w.addBox(at(2.2, 3.9, 0.425), {1.2, 0.6, 0.05}, wood, "coffee_table_top");
  for (double dx : {-0.55, 0.55})
    for (double dy : {-0.25, 0.25})
      w.addBox(at(2.2 + dx, 3.9 + dy, 0.2), {0.05, 0.05, 0.4}, wood, "coffee_table_leg", false);
  w.addBox(at(2.0, 3.85, 0.5), {0.3, 0.22, 0.05},
           mat(Pattern::kPoster, c(1, 1, 1), c(0, 0, 0), 0.06, s + 31), "book_on_table");
  // TV stand and TV against the south wall.
  w.addBox(at(1.8, 0.25, 0.25), {1.6, 0.45, 0.5},
           mat(Pattern::kTiles, c(0.30, 0.30, 0.32), c(0.10, 0.10, 0.10), 0.4, s + 40), "tv_stand",
           false);
  w.addBox(at(1.8, 0.15, 0.9), {1.2, 0.08, 0.7},
           mat(Pattern::kPlain, c(0.08, 0.08, 0.09), c(0, 0, 0), 0.5, s + 41), "tv");
  w.addQuad({2.35, 0.1901, 0.6}, -X, Z, 1.1, 0.6,
            mat(Pattern::kPoster, c(1, 1, 1), c(0, 0, 0), 0.12, s + 42), "tv_screen", false);
  // Bookshelf on the west wall: a case and rows of books.
  w.addBox(at(0.2, 2.4, 1.0), {0.4, 1.8, 2.0},
           mat(Pattern::kPlanks, c(0.70, 0.55, 0.35), c(0.40, 0.30, 0.18), 0.6, s + 50),
           "bookshelf", false);
  for (int row = 0; row < 4; ++row)
    w.addBox(at(0.43, 2.4, 0.3 + 0.45 * row), {0.06, 1.6, 0.3},
             mat(Pattern::kPoster, c(1, 1, 1), c(0, 0, 0), 0.07, s + 51 + row), "books", false);
  // Dining table with legs and two chairs near the east wall.
  w.addBox(at(6.0, 2.0, 0.75), {1.6, 0.9, 0.05}, wood, "dining_table_top");
  for (double dx : {-0.75, 0.75})
    for (double dy : {-0.4, 0.4})
      w.addBox(at(6.0 + dx, 2.0 + dy, 0.3625), {0.06, 0.06, 0.725}, wood, "dining_table_leg",
               false);
  const Material chair =
      mat(Pattern::kChecker, c(0.75, 0.20, 0.15), c(0.35, 0.10, 0.08), 0.12, s + 60);
  for (double y : {1.2, 2.8}) {
    const double back = y < 2.0 ? y - 0.22 : y + 0.22;
    w.addBox(at(6.0, y, 0.45), {0.45, 0.45, 0.05}, chair, "chair_seat");
    w.addBox(at(6.0, back, 0.75), {0.45, 0.04, 0.55}, chair, "chair_back", false);
    for (double dx : {-0.2, 0.2})
      for (double dy : {-0.2, 0.2})
        w.addBox(at(6.0 + dx, y + dy, 0.2125), {0.04, 0.04, 0.425}, chair, "chair_leg", false);
  }
  // Cabinet in the north-east corner, a floor lamp, a plant pot.
  w.addBox(at(7.6, 5.2, 0.6), {0.7, 1.2, 1.2},
           mat(Pattern::kTiles, c(0.85, 0.85, 0.80), c(0.20, 0.20, 0.20), 0.3, s + 70), "cabinet",
           false);
  w.addBox(at(3.3, 5.6, 0.8), {0.04, 0.04, 1.6},
           mat(Pattern::kPlain, c(0.2, 0.2, 0.2), c(0, 0, 0), 0.5, s + 71), "lamp_pole", false);
  w.addBox(at(3.3, 5.6, 1.7), {0.4, 0.4, 0.3},
           mat(Pattern::kChecker, c(0.95, 0.90, 0.70), c(0.80, 0.70, 0.45), 0.1, s + 72),
           "lamp_shade");
  w.addBox(at(4.6, 0.4, 0.25, 0.3), {0.4, 0.4, 0.5},
           mat(Pattern::kBricks, c(0.70, 0.40, 0.25), c(0.30, 0.20, 0.15), 0.2, s + 73),
           "plant_pot", false);
  w.addBox(at(4.6, 0.4, 0.8, 0.7), {0.5, 0.5, 0.6},
           mat(Pattern::kNoise, c(0.20, 0.55, 0.20), c(0.05, 0.25, 0.08), 0.15, s + 74), "plant");
  return w;
}

RoadPath blockLoop(double length, double width, double r, double step) {
  if (!(length > 2 * r) || !(width > 2 * r) || !(r > 0.0) || !(step > 0.0))
    throw InputError("sim3d blockLoop: expected length, width > 2 * radius > 0 and step > 0");
  // Walk the rounded rectangle's perimeter by arc length.
  const double a = 0.5 * length - r, b = 0.5 * width - r;
  const double straight_x = 2 * a, straight_y = 2 * b, arc = 0.5 * M_PI * r;
  const double total = 2 * straight_x + 2 * straight_y + 4 * arc;
  RoadPath path;
  const int n = static_cast<int>(std::ceil(total / step));
  for (int i = 0; i <= n; ++i) {
    double d = std::fmod(total * i / n, total);
    // Segments counter-clockwise starting at (-a, -b - r) heading +x.
    const double seg[8] = {straight_x, arc, straight_y, arc, straight_x, arc, straight_y, arc};
    int k = 0;
    while (k < 7 && d > seg[k]) d -= seg[k++];
    Eigen::Vector2d p;
    switch (k) {
      case 0:
        p = {-a + d, -b - r};
        break;
      case 1: {
        const double t = -M_PI / 2 + d / r;
        p = {a + r * std::cos(t), -b + r * std::sin(t)};
        break;
      }
      case 2:
        p = {a + r, -b + d};
        break;
      case 3: {
        const double t = d / r;
        p = {a + r * std::cos(t), b + r * std::sin(t)};
        break;
      }
      case 4:
        p = {a - d, b + r};
        break;
      case 5: {
        const double t = M_PI / 2 + d / r;
        p = {-a + r * std::cos(t), b + r * std::sin(t)};
        break;
      }
      case 6:
        p = {-a - r, b - d};
        break;
      default: {
        const double t = M_PI + d / r;
        p = {-a + r * std::cos(t), -b + r * std::sin(t)};
        break;
      }
    }
    path.emplace_back(p.x(), p.y(), 0.0);
  }
  return path;
}

namespace {

// Horizontal footprint of a building: centre, unit axis along the street, half sizes.
struct Footprint {
  Eigen::Vector2d c, a;
  double ha, hb;
  Eigen::Vector2d b() const { return {-a.y(), a.x()}; }
};

bool overlaps(const Footprint& p, const Footprint& q) {
  // Separating axis test on the four edge normals.
  for (const Eigen::Vector2d& axis : {p.a, p.b(), q.a, q.b()}) {
    const double rp = p.ha * std::abs(p.a.dot(axis)) + p.hb * std::abs(p.b().dot(axis));
    const double rq = q.ha * std::abs(q.a.dot(axis)) + q.hb * std::abs(q.b().dot(axis));
    if (std::abs((q.c - p.c).dot(axis)) > rp + rq) return false;
  }
  return true;
}

// Uniform 2D grid over path samples for "how close is the road" queries.
class PathIndex {
 public:
  PathIndex(const RoadPath& path, double cell) : cell_(cell) {
    for (size_t i = 0; i < path.size(); ++i) {
      pts_.push_back(path[i].head<2>());
      cells_[key(pts_.back())].push_back(static_cast<int>(i));
    }
  }
  // Distance from p to the path polyline if below `radius`, else radius.
  double distance(const Eigen::Vector2d& p, double radius) const {
    double best = radius;
    const int64_t cx = static_cast<int64_t>(std::floor(p.x() / cell_));
    const int64_t cy = static_cast<int64_t>(std::floor(p.y() / cell_));
    const int64_t r = static_cast<int64_t>(std::ceil(radius / cell_)) + 1;
    for (int64_t i = cx - r; i <= cx + r; ++i)
      for (int64_t j = cy - r; j <= cy + r; ++j) {
        auto it = cells_.find(pack(i, j));
        if (it == cells_.end()) continue;
        for (int k : it->second) {
          for (int m : {k - 1, k}) {
            if (m < 0 || m + 1 >= static_cast<int>(pts_.size())) continue;
            const Eigen::Vector2d a = pts_[m], d = pts_[m + 1] - a;
            const double len2 = d.squaredNorm();
            const double t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
            best = std::min(best, (a + t * d - p).norm());
          }
        }
      }
    return best;
  }

 private:
  // Shifted as unsigned: a left shift of a negative cell index is undefined before C++20.
  static int64_t pack(int64_t i, int64_t j) {
    return static_cast<int64_t>((static_cast<uint64_t>(i) << 32) ^
                                (static_cast<uint64_t>(j) & 0xFFFFFFFFu));
  }
  int64_t key(const Eigen::Vector2d& p) const {
    return pack(static_cast<int64_t>(std::floor(p.x() / cell_)),
                static_cast<int64_t>(std::floor(p.y() / cell_)));
  }
  double cell_;
  std::vector<Eigen::Vector2d> pts_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
};

}  // namespace

World World::street(const RoadPath& path, const StreetOptions& o, uint64_t seed) {
  if (path.size() < 2) throw InputError("sim3d street: the road path needs at least two points");
  if (!(o.road_half_width > 0) || !(o.sidewalk >= 0) || !(o.min_building > 0) ||
      !(o.max_building >= o.min_building) || !(o.min_height > 0) ||
      !(o.max_height >= o.min_height) || !(o.gap >= 0))
    throw InputError("sim3d street: building and road sizes must be positive, min <= max");
  World w;
  sim2d::Rng rng(seed, 31);
  const uint32_t s = static_cast<uint32_t>(seed * 0x9E3779B1u);
  const Eigen::Vector3d Z = Eigen::Vector3d::UnitZ();
  Material asphalt = mat(Pattern::kNoise, {0.32, 0.32, 0.34}, {0.18, 0.18, 0.19}, 1.5, s + 1);
  asphalt.world_uv = true;
  Material pavement = mat(Pattern::kTiles, {0.62, 0.60, 0.56}, {0.35, 0.35, 0.33}, 0.6, s + 2);
  pavement.world_uv = true;
  const Material paint = mat(Pattern::kPlain, {0.95, 0.95, 0.92}, {0, 0, 0}, 1.0, s + 3);

  // Road ribbon: one object per path segment (asphalt + two sidewalks + a dash or two).
  double dash_phase = 0.0;
  for (size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector3d p0 = path[i], d = path[i + 1] - path[i];
    const double len = d.norm();
    if (!(len > 1e-6)) continue;
    const Eigen::Vector2d hd = d.head<2>().normalized();
    if (!hd.allFinite()) continue;
    const Eigen::Vector3d u = d / len, lat(-hd.y(), hd.x(), 0.0);
    const double ext = 0.5;  // overlap neighbours so turns leave no gaps
    const Eigen::Vector3d start = p0 - ext * u;
    const double rw = o.road_half_width;
    w.beginObject("road");
    auto quad = [&](const Eigen::Vector3d& origin, double width, double height, const Material& m) {
      Face q;
      q.origin = origin;
      q.u = u;
      q.v = lat;
      q.normal = u.cross(lat);
      q.width = width;
      q.height = height;
      q.two_sided = true;
      q.material = m;
      w.pushFace(q);
    };
    quad(start - rw * lat, len + 2 * ext, 2 * rw, asphalt);
    quad(start - (rw + o.sidewalk + 4.0) * lat + 0.12 * Z, len + 2 * ext, o.sidewalk + 4.0,
         pavement);
    quad(start + rw * lat + 0.12 * Z, len + 2 * ext, o.sidewalk + 4.0, pavement);
    // Dashed lane lines 1.8 m either side of the path: 3 m painted every 9 m.
    for (double a = -dash_phase; a < len; a += 9.0) {
      const double b0 = std::max(a, 0.0), b1 = std::min(a + 3.0, len);
      if (b1 - b0 < 0.05) continue;
      for (double side : {-1.8, 1.8})
        quad(p0 + b0 * u + (side - 0.075) * lat + 0.01 * Z, b1 - b0, 0.15, paint);
    }
    dash_phase = std::fmod(dash_phase + len, 9.0);
  }

  // Buildings on both sides, never closer to the path than the kerb plus the sidewalk.
  const PathIndex index(path, 10.0);
  const double clearance = o.road_half_width + o.sidewalk - 0.5;
  std::vector<Footprint> placed;
  std::vector<double> arc(path.size(), 0.0);
  for (size_t i = 1; i < path.size(); ++i)
    arc[i] = arc[i - 1] + (path[i] - path[i - 1]).head<2>().norm();
  auto sample = [&](double a, Eigen::Vector3d* p, Eigen::Vector2d* dir) {
    size_t k = std::upper_bound(arc.begin(), arc.end(), a) - arc.begin();
    k = std::clamp<size_t>(k, 1, path.size() - 1);
    const double seg = arc[k] - arc[k - 1];
    const double t = seg > 0 ? (a - arc[k - 1]) / seg : 0.0;
    *p = path[k - 1] + t * (path[k] - path[k - 1]);
    *dir = (path[k] - path[k - 1]).head<2>().normalized();
  };
  const Pattern facades[3] = {Pattern::kWindows, Pattern::kBricks, Pattern::kWindows};
  int building = 0;
  for (int side : {-1, +1}) {
    for (double a = rng.uniform(0.0, 5.0); a < arc.back();) {
      const double frontage = rng.uniform(o.min_building, o.max_building);
      const double depth = rng.uniform(8.0, 16.0);
      const double height = rng.uniform(o.min_height, o.max_height);
      Eigen::Vector3d p;
      Eigen::Vector2d dir;
      sample(a + 0.5 * frontage, &p, &dir);
      a += frontage + o.gap * rng.uniform(0.3, 1.7);
      if (!dir.allFinite()) continue;
      const Eigen::Vector2d lat(-dir.y(), dir.x());
      Footprint fp{p.head<2>() + side * (clearance + 0.5 + 0.5 * depth) * lat, dir, 0.5 * frontage,
                   0.5 * depth};
      bool ok = true;
      for (double sa : {-1.0, 0.0, 1.0})
        for (double sb : {-1.0, 0.0, 1.0}) {
          const Eigen::Vector2d q = fp.c + sa * fp.ha * fp.a + sb * fp.hb * fp.b();
          if (index.distance(q, clearance) < clearance) ok = false;
        }
      for (const Footprint& other : placed)
        if (ok && (other.c - fp.c).norm() < 60.0 && overlaps(fp, other)) ok = false;
      const double car = rng.uniform();
      const int style = static_cast<int>(rng.index(3));
      const Eigen::Vector3d tint(rng.uniform(0.5, 1.0), rng.uniform(0.45, 0.9),
                                 rng.uniform(0.4, 0.85));
      if (!ok) continue;
      placed.push_back(fp);
      const double yaw = std::atan2(dir.y(), dir.x());
      const double base = p.z() - 1.0;  // sunk a metre so slopes leave no gap underneath
      Material facade = mat(facades[style], tint, {0.20, 0.28, 0.38}, style == 1 ? 0.9 : 2.5,
                            s + 100 + static_cast<uint32_t>(building));
      if (style == 1) facade.color_b = {0.75, 0.72, 0.68};
      w.addBox(at(fp.c.x(), fp.c.y(), base + 0.5 * (height + 1.0), yaw),
               {frontage, depth, height + 1.0}, facade, "building", false);
      ++building;
      if (car < o.parked_cars) {
        const Eigen::Vector2d cc = p.head<2>() + side * (o.road_half_width - 1.2) * lat;
        if (index.distance(cc, 3.0) >= 3.0) {
          const Eigen::Vector3d paint_color(rng.uniform(0.1, 0.9), rng.uniform(0.1, 0.9),
                                            rng.uniform(0.1, 0.9));
          w.addBox(at(cc.x(), cc.y(), p.z() + 0.75, yaw), {4.2, 1.8, 1.5},
                   mat(Pattern::kChecker, paint_color, paint_color * 0.4, 0.7,
                       s + 5000 + static_cast<uint32_t>(building)),
                   "car", false);
        }
      }
    }
  }
  return w;
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
