// The built-in office floor plan (64 x 40 m). Layout, y up:
//   y 28.5..40  five top rooms           (doors on the upper corridor, two rooms connected)
//   y 26..28.5  upper corridor           (full width)
//   y 14.5..26  two open-plan rooms left, one large room right, between three vertical corridors
//               at x 0..2.5, 30..32.5 and 61.5..64 (two corridor loops)
//   y 12..14.5  lower corridor           (full width)
//   y 0..12     six bottom rooms
// Corridor walls carry door gaps and alcoves, and rooms hold pillars and furniture boxes, so a
// scan anywhere has structure along both axes (a featureless corridor would make ICP slide).
#include <algorithm>
#include <cmath>
#include <vector>

#include "sim2d/world.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

// A door gap (depth 0), an alcove (a rectangular recess, depth > 0, towards the wall's left side
// when walking from a to b) or a column (depth < 0, protruding to the right side) along a wall.
struct Opening {
  double at;         // distance of its centre from the wall's first end point
  double width;      // along the wall
  double depth = 0;  // 0: door gap; signed offset of the recess or protrusion
};

constexpr double kDoor = 1.4;
// Structural columns along corridor walls: without them a corridor seen by one laser has almost
// no surface facing along its axis, and scan matching slides along it.
constexpr double kColumnSpacing = 5.0, kColumnWidth = 0.4, kColumnDepth = 0.25;

// A wall from a to b with its openings; column_side (+1 left, -1 right, 0 none) adds columns
// every kColumnSpacing metres where they do not touch an opening or the wall's ends.
void wall(std::vector<Segment>& out, Eigen::Vector2d a, Eigen::Vector2d b,
          std::vector<Opening> openings = {}, int column_side = 0) {
  const double length = (b - a).norm();
  if (column_side != 0) {
    std::vector<Opening> columns;
    for (double at = 0.5 * kColumnSpacing; at < length - 0.7; at += kColumnSpacing) {
      bool clear = at > 0.7;
      for (const Opening& o : openings) {
        clear = clear && std::abs(o.at - at) > 0.5 * (o.width + kColumnWidth) + 0.5;
      }
      if (clear) columns.push_back({at, kColumnWidth, column_side * kColumnDepth});
    }
    openings.insert(openings.end(), columns.begin(), columns.end());
  }
  const Eigen::Vector2d u = (b - a) / length;
  const Eigen::Vector2d left(-u.y(), u.x());
  double s = 0.0;
  std::sort(openings.begin(), openings.end(),
            [](const Opening& x, const Opening& y) { return x.at < y.at; });
  for (const Opening& o : openings) {
    const double s0 = o.at - 0.5 * o.width, s1 = o.at + 0.5 * o.width;
    if (s0 > s) out.push_back({a + s * u, a + s0 * u});
    if (o.depth != 0.0) {
      const Eigen::Vector2d p0 = a + s0 * u, p1 = a + s1 * u, off = o.depth * left;
      out.push_back({p0, p0 + off});
      out.push_back({p0 + off, p1 + off});
      out.push_back({p1 + off, p1});
    }
    s = s1;
  }
  if (s < length) out.push_back({a + s * u, b});
}

// An axis-aligned box (pillar, desk, cabinet) given by centre and size.
void box(std::vector<Segment>& out, double cx, double cy, double w, double h) {
  const Eigen::Vector2d p0(cx - 0.5 * w, cy - 0.5 * h), p1(cx + 0.5 * w, cy - 0.5 * h),
      p2(cx + 0.5 * w, cy + 0.5 * h), p3(cx - 0.5 * w, cy + 0.5 * h);
  out.push_back({p0, p1});
  out.push_back({p1, p2});
  out.push_back({p2, p3});
  out.push_back({p3, p0});
}

using V = Eigen::Vector2d;

}  // namespace

World World::office() {
  std::vector<Segment> s;
  // Outer walls.
  wall(s, V(0, 0), V(64, 0));
  wall(s, V(64, 0), V(64, 40));
  wall(s, V(64, 40), V(0, 40));
  wall(s, V(0, 40), V(0, 0));

  // Lower corridor (y 12..14.5). Left side of a->b (x increasing) is +y: alcoves with negative
  // depth would need the other orientation, so bottom-side alcoves use walls drawn right-to-left.
  wall(s, V(64, 12), V(0, 12),
       {{64 - 61, kDoor},
        {64 - 55, kDoor},
        {64 - 45, kDoor},
        {64 - 39.5, 1.5, 0.8},
        {64 - 37, kDoor},
        {64 - 29, kDoor},
        {64 - 23, kDoor},
        {64 - 17, kDoor},
        {64 - 12.5, 1.5, 0.8},
        {64 - 5, kDoor}},
       -1);
  wall(s, V(2.5, 14.5), V(30, 14.5), {{8 - 2.5, kDoor}, {12 - 2.5, 1.5, 0.8}, {24 - 2.5, kDoor}},
       -1);
  wall(s, V(32.5, 14.5), V(61.5, 14.5),
       {{38 - 32.5, kDoor}, {43 - 32.5, 2.0, 0.8}, {55 - 32.5, kDoor}}, -1);

  // Upper corridor (y 26..28.5): bottom side drawn right-to-left so alcoves go into the rooms.
  wall(s, V(30, 26), V(2.5, 26), {{30 - 20, kDoor}, {30 - 10, kDoor}, {30 - 25, 1.5, 0.8}}, -1);
  wall(s, V(61.5, 26), V(32.5, 26), {{61.5 - 50, 1.5, 0.8}, {61.5 - 46, kDoor}, {61.5 - 36, kDoor}},
       -1);
  wall(s, V(0, 28.5), V(64, 28.5),
       {{6, kDoor},
        {14, kDoor},
        {18, 1.5, 0.8},
        {22, kDoor},
        {30, kDoor},
        {33.5, 1.5, 0.8},
        {42, kDoor},
        {51, kDoor},
        {60, kDoor}},
       -1);

  // Vertical corridor walls in the middle band (y 14.5..26), with doors into the big rooms.
  wall(s, V(2.5, 14.5), V(2.5, 26), {{20 - 14.5, kDoor}});
  wall(s, V(30, 14.5), V(30, 26), {{17 - 14.5, kDoor}, {22.5 - 14.5, 1.5, 0.6}});
  wall(s, V(32.5, 14.5), V(32.5, 26), {{22 - 14.5, kDoor}});
  wall(s, V(61.5, 14.5), V(61.5, 26), {{18 - 14.5, kDoor}, {23 - 14.5, 1.5, 0.6}});
  wall(s, V(16, 14.5), V(16, 26), {{20 - 14.5, kDoor}});  // ML1 | ML2, connected

  // Bottom room dividers (y 0..12); two pairs of rooms are connected.
  wall(s, V(10, 0), V(10, 12));
  wall(s, V(20, 0), V(20, 12), {{4, kDoor}});
  wall(s, V(32, 0), V(32, 12));
  wall(s, V(42, 0), V(42, 12), {{6, kDoor}});
  wall(s, V(52, 0), V(52, 12));
  // Top room dividers (y 28.5..40).
  wall(s, V(12, 28.5), V(12, 40), {{36 - 28.5, kDoor}});
  wall(s, V(24, 28.5), V(24, 40));
  wall(s, V(36, 28.5), V(36, 40), {{34 - 28.5, kDoor}});
  wall(s, V(48, 28.5), V(48, 40));

  // Furniture and pillars.
  box(s, 3, 2, 2.0, 0.8);       // R1 desk
  box(s, 9.2, 6, 0.8, 1.6);     // R1 cabinet
  box(s, 6, 7, 0.5, 0.5);       // R1 pillar
  box(s, 15, 5, 2.4, 1.2);      // R2 table
  box(s, 18.5, 1.0, 1.6, 0.8);  // R2 desk
  box(s, 24, 6, 0.5, 0.5);      // R3 pillars
  box(s, 28, 6, 0.5, 0.5);
  box(s, 26, 1.2, 3.0, 0.8);  // R3 desk
  box(s, 34, 3, 1.6, 1.6);    // R4 cabinet
  box(s, 39, 8, 0.5, 0.5);    // R4 pillar
  box(s, 47, 1, 2.4, 0.8);    // R5 desk
  box(s, 50.8, 8, 0.8, 2.0);  // R5 cabinet
  box(s, 56, 5, 0.6, 0.6);    // R6 pillars and table
  box(s, 60, 5, 0.6, 0.6);
  box(s, 58, 1.2, 2.0, 0.8);
  box(s, 5.5, 17.5, 2.4, 1.2);   // ML1 table
  box(s, 12.5, 23, 0.5, 0.5);    // ML1 pillar
  box(s, 14.8, 16.2, 1.6, 0.8);  // ML1 desk
  box(s, 20, 18, 0.5, 0.5);      // ML2 pillars
  box(s, 26, 18, 0.5, 0.5);
  box(s, 20, 23, 0.5, 0.5);
  box(s, 26, 23, 0.5, 0.5);
  box(s, 40, 20.25, 0.6, 0.6);  // MR pillars and desks
  box(s, 47, 20.25, 0.6, 0.6);
  box(s, 54, 20.25, 0.6, 0.6);
  box(s, 37, 16.5, 2.0, 0.8);
  box(s, 44, 24, 2.0, 0.8);
  box(s, 51, 16.5, 2.0, 0.8);
  box(s, 58, 24, 2.0, 0.8);
  box(s, 3, 38, 2.0, 1.2);  // T1
  box(s, 8, 33, 0.5, 0.5);
  box(s, 18, 34, 3.0, 1.2);  // T2
  box(s, 28, 33, 0.5, 0.5);  // T3
  box(s, 32, 36, 0.5, 0.5);
  box(s, 46.8, 38, 1.6, 2.0);  // T4
  box(s, 40, 39, 2.0, 0.8);
  box(s, 54, 34, 0.6, 0.6);  // T5
  box(s, 58, 34, 0.6, 0.6);
  box(s, 63.3, 36, 0.8, 3.0);
  return World(std::move(s));
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
