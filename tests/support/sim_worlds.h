#pragma once
// Worlds for the 2D simulator (sim.Simulator2D's segment-list format) that tests need beside
// the built-in office.
#include <cmath>
#include <fstream>
#include <string>
#include <utility>

namespace plugslam::testing {

/// Writes to `path` a hall of seven unequal sides with three pillars, centred on the origin
/// (start the simulator at [0, 0]): no place of it looks like the office's rooms and corridors.
inline void writeSevenSidedHall(const std::string& path) {
  std::ofstream out(path);
  const double r[7] = {7, 6, 8, 5.5, 7.5, 6.5, 5};
  for (int i = 0; i < 7; ++i) {
    const double a0 = 2 * M_PI * i / 7, a1 = 2 * M_PI * (i + 1) / 7;
    out << r[i] * std::cos(a0) << " " << r[i] * std::sin(a0) << " "
        << r[(i + 1) % 7] * std::cos(a1) << " " << r[(i + 1) % 7] * std::sin(a1) << "\n";
  }
  for (const auto& [x, y] : {std::pair{2.0, 1.0}, std::pair{-2.0, 2.5}, std::pair{0.5, -3.0}})
    out << x << " " << y << " " << x + 0.6 << " " << y << "\n"
        << x + 0.6 << " " << y << " " << x + 0.6 << " " << y + 0.6 << "\n"
        << x + 0.6 << " " << y + 0.6 << " " << x << " " << y + 0.6 << "\n"
        << x << " " << y + 0.6 << " " << x << " " << y << "\n";
}

}  // namespace plugslam::testing
