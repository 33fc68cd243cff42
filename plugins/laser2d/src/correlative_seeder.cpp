#include "correlative_seeder.h"

#include <spdlog/spdlog.h>

#include "plugslam/errors.h"

namespace plugslam {
namespace laser2d {

void CorrelativeSeeder::configure() {
  if (resolution() > linear_window() && linear_window() > 0)
    throw ParamError("resolution", "must not exceed linear_window");
}

std::vector<SE2> CorrelativeSeeder::search(const AlignContext<Space2D>& context) {
  if (measurement->empty() || scene->empty()) return {};
  // Measured motion puts the prediction within the tracker's gate; a search over a wider window
  // can only add the scan's look-alike places (a corridor's slides), so it may be left to the
  // frames whose motion was not measured, or only in part (the rest extrapolated).
  if (context.motionMeasuredInFull() && !with_measured_motion()) return {};
  const double r = resolution();
  const std::vector<Eigen::Vector2d> query = correlativeQuery(measurement->points, max_range(), r);
  if (query.empty()) return {};
  CorrelativeOptions o;
  o.linear_window = linear_window();
  o.angular_window = angular_window();
  o.angular_step = angular_step();
  o.min_score = min_score();
  o.min_score_margin = min_score_margin();
  // Only the part of the map the scan can reach from the window is rasterized.
  const SE2& g = context.guess;
  const Eigen::Vector2d reach = Eigen::Vector2d::Constant(max_range() + linear_window() + r);
  const CorrelativeGrid grid(scene->points, scene->normals, point_extent(), r,
                             correlativeLevels(linear_window(), r), g.translation() - reach,
                             g.translation() + reach);
  const CorrelativeMatch m = matchCorrelative(grid, query, g, o);
  if (!m.found || m.ambiguous) {
    spdlog::debug("frame {}: correlative search around the prediction: {}", context.seq,
                  m.found ? "ambiguous (" + std::to_string(m.score) + " vs " +
                                std::to_string(m.second_score) + ")"
                          : "no pose scores " + std::to_string(min_score()));
    return {};
  }
  return {m.pose};
}

}  // namespace laser2d
}  // namespace plugslam
