#include "simulator2d_source.h"

#include <algorithm>
#include <set>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  std::string tail = s.substr(s.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == suffix;
}

}  // namespace

Simulator2DSource::Simulator2DSource() = default;
Simulator2DSource::~Simulator2DSource() = default;

void Simulator2DSource::configure() {
  sim2d::SimConfig config = sim2d::presetSession(session(), static_cast<uint64_t>(seed()));

  // Lasers: the rig's scanners named in `lasers`, in that order.
  if (lasers().empty()) throw ParamError("lasers", "needs at least one scanner name");
  std::vector<sim2d::LaserConfig> chosen;
  std::set<std::string> seen;
  for (const auto& name : lasers()) {
    if (!seen.insert(name).second) throw ParamError("lasers", "'" + name + "' listed twice");
    auto it = std::find_if(config.lasers.begin(), config.lasers.end(),
                           [&](const sim2d::LaserConfig& l) { return l.name == name; });
    if (it == config.lasers.end()) {
      std::string known;
      for (const auto& l : config.lasers) known += (known.empty() ? "" : ", ") + l.name;
      throw ParamError("lasers", "unknown scanner '" + name + "'; the rig has: " + known);
    }
    chosen.push_back(*it);
    chosen.back().range_sigma = range_noise();
    chosen.back().dropout = dropout();
  }
  config.lasers = std::move(chosen);
  for (const auto& name : lasers()) {
    if (name == odometry() || name == ground_truth()) {
      throw ParamError("lasers", "'" + name + "' clashes with the odometry or ground_truth entry");
    }
  }
  if (odometry() == ground_truth()) throw ParamError("odometry", "must differ from ground_truth");

  config.odometry = config.odometry.scaled(odometry_noise());

  if (!world().empty()) {
    if (world_origin().size() != 2) throw ParamError("world_origin", "expected [x, y]");
    if (start().size() != 2) {
      throw ParamError("start", "a custom world needs a start place [x, y] (free space)");
    }
    const Eigen::Vector2d origin(world_origin()[0], world_origin()[1]);
    config.world = std::make_shared<const sim2d::World>(
        endsWith(world(), ".pgm") ? sim2d::World::loadPgm(world(), world_resolution(), origin)
                                  : sim2d::World::loadSegments(world()));
    // The presets' tours are places in the office; elsewhere the robot explores from `start`.
    config.tour = {Eigen::Vector2d(start()[0], start()[1])};
  } else if (!start().empty()) {
    throw ParamError("start", "only used with a custom world (the presets follow their tour)");
  }
  sim_ = std::make_unique<sim2d::Simulator>(std::move(config));
}

const sim2d::Simulator& Simulator2DSource::simulator() const {
  if (!sim_) throw InputError("sim.Simulator2D: configure() was not called");
  return *sim_;
}

std::vector<ProvidedEntry> Simulator2DSource::provides() const {
  std::vector<ProvidedEntry> out;
  for (const auto& name : lasers()) out.push_back({name, typeid(LaserScan)});
  out.push_back({odometry(), typeid(Odometry2D)});
  out.push_back({ground_truth(), typeid(Eigen::Isometry2d)});
  return out;
}

int64_t Simulator2DSource::sizeHint() const {
  return sim_ ? static_cast<int64_t>(sim_->frameCount()) : -1;
}

bool Simulator2DSource::next(Frame& frame) {
  if (!sim_) configure();
  sim2d::SimFrame f;
  if (!sim_->step(f)) return false;
  frame.stamp = f.time;
  for (auto& s : f.lasers) {
    LaserScan scan;
    scan.stamp = f.time;
    scan.angle_min = s.angle_min;
    scan.angle_increment = s.angle_increment;
    scan.range_min = s.min_range;
    scan.range_max = s.max_range;
    scan.ranges = std::move(s.ranges);
    scan.mount = sim2d::toIsometry(s.mount);
    frame.raw.set<LaserScan>(s.name, std::move(scan));
  }
  frame.raw.set<Odometry2D>(odometry(), {f.time, sim2d::toIsometry(f.odometry)});
  frame.raw.set<Eigen::Isometry2d>(ground_truth(), sim2d::toIsometry(f.ground_truth));
  return true;
}

}  // namespace sim
}  // namespace plugslam
