#pragma once
// The 3D simulator's world: textured rectangles (planes) and boxes, grouped into objects with
// bounding boxes for culling. Two built-in worlds: an ICL-NUIM-like living room and a
// KITTI-like street of buildings along a road path.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace plugslam {
namespace sim {
namespace sim3d {

/// Procedural patterns, all with many corners so FAST/ORB-like detectors find features.
enum class Pattern {
  kChecker,  ///< squares of side `scale`
  kBricks,   ///< bricks scale x scale/3 in staggered rows with mortar, per-brick tone
  kNoise,    ///< contrast-stretched value noise, blobs of about `scale`
  kWindows,  ///< facade: wall with a grid of dark windows (cell `scale`)
  kPlanks,   ///< wooden floor: staggered planks of width scale/5 with grain
  kTiles,    ///< tiles of side `scale` with grout and per-tile tone
  kPoster,   ///< grid of cells of side `scale` in random palette colours (pictures, books)
  kPlain,    ///< color_a with faint noise (ceilings, sky-like surfaces)
};

/// What a surface looks like. Colours are RGB albedos in [0, 1].
struct Material {
  Pattern pattern = Pattern::kNoise;       ///< the pattern
  Eigen::Vector3d color_a{0.7, 0.7, 0.7};  ///< main colour
  Eigen::Vector3d color_b{0.3, 0.3, 0.3};  ///< second colour (squares, mortar, windows)
  double scale = 0.5;                      ///< pattern cell size [m]
  uint32_t seed = 0;                       ///< varies the pattern between faces
  bool world_uv = false;  ///< texture by world (x, y) instead of face coordinates (roads)
};

/// A rectangle origin + s * u + t * v, s in [0, width], t in [0, height]; u, v orthonormal.
struct Face {
  Eigen::Vector3d origin{0, 0, 0};  ///< corner at (s, t) = (0, 0)
  Eigen::Vector3d u{1, 0, 0};       ///< first edge direction (unit)
  Eigen::Vector3d v{0, 1, 0};       ///< second edge direction (unit, orthogonal to u)
  Eigen::Vector3d normal{0, 0, 1};  ///< u x v; the visible side of a one-sided face
  double width = 1.0;               ///< extent along u [m]
  double height = 1.0;              ///< extent along v [m]
  bool two_sided = true;            ///< false: seen only from the side the normal points to
  Material material;                ///< appearance
  int object = -1;                  ///< index of the object it belongs to
};

/// A named group of faces (one box, one wall) with its bounding box.
struct Object {
  std::string name;            ///< for debugging and tests
  Eigen::AlignedBox3d bounds;  ///< bounding box of its faces
  int first_face = 0;          ///< faces [first_face, first_face + face_count)
  int face_count = 0;          ///< number of faces
};

/// Result of World::castRay.
struct RayHit {
  double distance = 0.0;           ///< along the (unit) ray [m]
  int face = -1;                   ///< index of the face hit
  Eigen::Vector3d point{0, 0, 0};  ///< hit point in the world
};

/// A road path sample for World::street: the road surface centre [m].
using RoadPath = std::vector<Eigen::Vector3d>;

/// Layout of a street world.
struct StreetOptions {
  double road_half_width = 6.0;  ///< asphalt from the path centre to the kerb [m]
  double sidewalk = 3.0;         ///< kerb to the first building line [m]
  double min_building = 8.0;     ///< building frontage range [m]
  double max_building = 22.0;    ///< [m]
  double min_height = 6.0;       ///< building height range [m]
  double max_height = 24.0;      ///< [m]
  double gap = 2.0;              ///< mean gap between buildings [m]
  double parked_cars = 0.3;      ///< probability of a parked car box per building
};

/// A world of rectangles and boxes (z up).
class World {
 public:
  /// Adds a rectangle as its own object; u_dir, v_dir are made orthonormal (v_dir is
  /// orthogonalised against u_dir); throws InputError on degenerate input.
  void addQuad(const Eigen::Vector3d& origin, const Eigen::Vector3d& u_dir,
               const Eigen::Vector3d& v_dir, double width, double height, const Material& material,
               const std::string& name, bool two_sided = true);

  /// Adds a box with its centre and orientation at `pose` and full edge lengths `size`; six
  /// outward one-sided faces (five when with_bottom is false), each with its own pattern seed.
  void addBox(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, const Material& material,
              const std::string& name, bool with_bottom = true);

  /// Nearest hit along the ray from origin in the unit direction within (min_range, max_range];
  /// false if nothing is hit.
  bool castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double max_range,
               RayHit* hit, double min_range = 0.0) const;

  /// The segments where the horizontal plane z = height cuts the faces (a 2D floor plan).
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> slice(double height) const;

  /// All faces.
  const std::vector<Face>& faces() const { return faces_; }
  /// All objects.
  const std::vector<Object>& objects() const { return objects_; }
  /// Bounding box of everything.
  const Eigen::AlignedBox3d& bounds() const { return bounds_; }

  /// An ICL-NUIM-like living room, 8 x 6 x 2.7 m (floor z = 0, corner at the origin): planked
  /// floor, brick and painted walls, windows, door, sofa, tables with legs, shelves with books,
  /// TV, pictures and a rug. `seed` varies the textures only.
  static World livingRoom(uint64_t seed = 0);

  /// A street along `path` (road surface centres, metres apart): a road ribbon following the
  /// path's heights, lane markings, and building boxes on both sides, kept off the road even
  /// where the path passes again; `seed` draws the buildings and textures.
  static World street(const RoadPath& path, const StreetOptions& options = {}, uint64_t seed = 0);

 private:
  int beginObject(const std::string& name);
  void pushFace(Face f);

  std::vector<Face> faces_;
  std::vector<Object> objects_;
  Eigen::AlignedBox3d bounds_;
};

/// The albedo (RGB in [0, 1]) of a face's material at face coordinates (s, t) and world point p.
/// `footprint` is the surface size of one pixel there [m]; detail smaller than about a pixel
/// fades to the pattern's average colour (0 = full detail).
Eigen::Vector3d albedo(const Material& m, double s, double t, const Eigen::Vector3d& p,
                       double footprint = 0.0);

/// A flat rounded-rectangle loop of `length` x `width` metres centred at the origin, sampled
/// every `step` metres (the built-in street's road path).
RoadPath blockLoop(double length, double width, double corner_radius, double step);

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
