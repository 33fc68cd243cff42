// The seed's four simulated sessions (section V-A): a differential-drive robot with a front and
// a rear laser and wheel encoders at 10 Hz, on paths of 43.191, 79.146, 480.741 and 627.709 m.
// Each preset tours the built-in office; the session stops at the first frame past the seed's
// length, so the longer sessions drive their tour more than once and revisit places.
#include <memory>

#include "plugslam/errors.h"
#include "sim2d/simulator.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

using V = Eigen::Vector2d;

struct Preset {
  const char* name;
  double length;
  std::vector<V> tour;
};

// Places in the office (see office.cpp): corridor centre lines are y 13.25 and 27.25 and
// x 1.25, 31.25 and 62.75.
const std::vector<Preset>& presets() {
  static const std::vector<Preset> table = {
      // A small loop: lower corridor, the left open-plan room, the left corridor, and back.
      {"stage-0", 43.191, {V(6, 13.25), V(9, 21), V(1.25, 20)}},
      // A loop through both open-plan rooms and back along the lower corridor.
      {"stage-1", 79.146, {V(1.25, 13.25), V(24, 13.25), V(23, 20.5), V(9, 21), V(1.25, 20)}},
      // Bottom-left rooms, the big right room, the right corridor, the top rooms and the two
      // open-plan rooms, then again.
      {"stage-2",
       480.741,
       {V(1.25, 13.25), V(5, 5), V(14, 8.5), V(26, 8.5), V(31.25, 13.25), V(44, 18.5), V(62.75, 20),
        V(62.75, 27.25), V(56, 37), V(42, 34), V(30, 34.5), V(31.25, 27.25), V(23, 20.5), V(9, 21),
        V(1.25, 27.25), V(6, 34), V(1.25, 20)}},
      // Every room, anticlockwise, crossing the centre corridor twice (figure-eight loops).
      {"stage-3",
       627.709,
       {V(31.25, 20),    V(44, 18.5), V(58, 8.5), V(46, 5),       V(37, 6.5),    V(31.25, 13.25),
        V(26, 8.5),      V(14, 8.5),  V(5, 5),    V(1.25, 20),    V(9, 21),      V(23, 20.5),
        V(31.25, 27.25), V(42, 34),   V(56, 37),  V(62.75, 20),   V(55, 22.5),   V(31.25, 22),
        V(30, 34.5),     V(18, 31.5), V(6, 34),   V(1.25, 27.25), V(1.25, 13.25)}},
  };
  return table;
}

const Preset& find(const std::string& name) {
  for (const Preset& p : presets()) {
    if (name == p.name) return p;
  }
  std::string known;
  for (const Preset& p : presets()) known += (known.empty() ? "" : ", ") + std::string(p.name);
  throw InputError("sim2d: unknown session '" + name + "', expected one of: " + known);
}

}  // namespace

std::vector<LaserConfig> defaultLasers() {
  LaserConfig front;
  front.name = "front_laser";
  front.mount = Eigen::Vector3d(0.2, 0.0, 0.0);
  front.fov = 1.5 * M_PI;
  front.beams = 1081;
  front.min_range = 0.05;
  front.max_range = 30.0;
  front.range_sigma = 0.01;
  front.dropout = 0.005;
  LaserConfig rear = front;
  rear.name = "rear_laser";
  rear.mount = Eigen::Vector3d(-0.2, 0.0, M_PI);
  return {front, rear};
}

SimConfig presetSession(const std::string& name, uint64_t seed) {
  const Preset& p = find(name);
  SimConfig c;
  // A fresh world per session: nothing outlives the caller (the sim plugin may be unloaded).
  c.world = std::make_shared<const World>(World::office());
  c.tour = p.tour;
  c.path_length = p.length;
  c.lasers = defaultLasers();
  c.seed = seed;
  return c;
}

std::vector<std::string> presetNames() {
  std::vector<std::string> names;
  for (const Preset& p : presets()) names.push_back(p.name);
  return names;
}

double presetSeedLength(const std::string& name) { return find(name).length; }

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
