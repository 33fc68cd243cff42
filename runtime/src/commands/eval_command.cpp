// plugslam eval ate|rpe|relations|crispness: score trajectories (TUM, KITTI, g2o) and maps.
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <set>

#include "cli.h"
#include "commands/commands.h"
#include "commands/introspection.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/eval/ate.h"
#include "plugslam/eval/crispness.h"
#include "plugslam/eval/relations.h"
#include "plugslam/eval/report.h"
#include "plugslam/eval/rpe.h"
#include "plugslam/registry.h"
#include "plugslam/sensor_data.h"
#include "plugslam/source.h"
#include "plugslam/trajectory.h"

namespace plugslam::runtime {

namespace {

struct EvalArgs {
  std::string reference, estimate, output, format = "md", align = "se3", unit = "frames";
  std::string relations_file, log, source_type, laser = "front_laser", ref_format = "auto",
                                                est_format = "auto";
  double delta = 1, max_dt = 0.01, max_distance = 1.0, radius = 0.3, max_range = 0;
  // Relations name scans by their exact stamps (RelationOptions).
  double relation_max_dt = RelationOptions{}.max_time_diff;
  int min_gap = 50;
  int max_gap = 0;
};

void emit(const EvalArgs& a, const std::string& md, const std::string& json) {
  const std::string& text = a.format == "json" ? json : md;
  if (a.output.empty())
    std::cout << text << (text.empty() || text.back() == '\n' ? "" : "\n");
  else
    writeFileAtomically(a.output, text);
}

Trajectory read(const std::string& path, const std::string& format) {
  return readTrajectory(path, parseTrajectoryFormat(format));
}

void addCommon(CLI::App* cmd, EvalArgs& a, double& max_dt,
               const std::string& max_dt_help = "max time difference when associating poses [s]") {
  cmd->add_option("--format", a.format, "output: md (markdown) or json")
      ->check(CLI::IsMember({"md", "json"}))
      ->capture_default_str();
  cmd->add_option("-o,--output", a.output, "write the result to this file (default: stdout)");
  cmd->add_option("--max-dt", max_dt, max_dt_help)->capture_default_str();
}

// Reads every scan of one laser from a log through the io plugin's sources.
std::vector<PosedScan> scansFromLog(const EvalArgs& a, const Trajectory& trajectory) {
  PluginManager plugins;
  std::string type = a.source_type;
  if (type.empty())
    type = a.log.size() > 4 && a.log.compare(a.log.size() - 4, 4, ".bag") == 0 ? "io.RosbagSource"
                                                                               : "io.CarmenSource";
  loadPluginOf(plugins, type);
  auto obj = Registry::instance().create(type);
  auto* source = dynamic_cast<Source*>(obj.get());
  if (!source) throw InputError("'" + type + "' is not a Source");
  auto* path = obj->findParam("path");
  if (!path) throw InputError("source '" + type + "' has no 'path' parameter");
  path->fromYaml(YAML::Node(a.log));
  obj->configure();
  std::vector<std::vector<Eigen::Vector2d>> points;
  std::vector<double> stamps;
  Frame frame;
  // Scans in the log's order; a stamp earlier than the previous one is the scan's own (sources
  // keep the log's stamps), only a repeated one could not be told apart in the trajectory.
  std::set<double> seen;
  while (source->next(frame)) {
    const LaserScan* scan = frame.raw.find<LaserScan>(a.laser);
    if (scan && std::isfinite(frame.stamp) && seen.insert(frame.stamp).second) {
      std::vector<Eigen::Vector2d> pts;
      for (size_t i = 0; i < scan->ranges.size(); ++i) {
        if (!scan->isReturn(i)) continue;
        if (a.max_range > 0 && scan->ranges[i] > a.max_range) continue;
        double r = scan->ranges[i], th = scan->angle(i);
        pts.push_back(scan->mount * Eigen::Vector2d(r * std::cos(th), r * std::sin(th)));
      }
      points.push_back(std::move(pts));
      stamps.push_back(frame.stamp);
    }
    frame = Frame();
  }
  if (points.empty()) throw InputError("no scans named '" + a.laser + "' in '" + a.log + "'");
  return placeScans(points, stamps, trajectory, a.max_dt);
}

}  // namespace

void addEvalCommand(CLI::App& root, int& exit_code) {
  auto* eval =
      root.add_subcommand("eval", "Score trajectories and maps: ate, rpe, relations, crispness");
  eval->require_subcommand(1);
  static EvalArgs a;

  auto* ate = eval->add_subcommand("ate", "Absolute trajectory error after alignment");
  ate->add_option("REFERENCE", a.reference, "reference trajectory (TUM, KITTI or g2o)")->required();
  ate->add_option("ESTIMATE", a.estimate, "estimated trajectory")->required();
  ate->add_option("--align", a.align, "alignment: none, se2, se3, sim3")
      ->check(CLI::IsMember({"none", "se2", "se3", "sim3"}))
      ->capture_default_str();
  addCommon(ate, a, a.max_dt);
  ate->callback([&exit_code] {
    AteOptions o;
    o.alignment = parseAlignment(a.align);
    o.association.max_time_diff = a.max_dt;
    auto r = computeAte(read(a.reference, a.ref_format), read(a.estimate, a.est_format), o);
    emit(a, toMarkdown(r), toJson(r));
    exit_code = kOk;
  });

  auto* rpe =
      eval->add_subcommand("rpe", "Relative pose error over a step in frames, metres or seconds");
  rpe->add_option("REFERENCE", a.reference, "reference trajectory")->required();
  rpe->add_option("ESTIMATE", a.estimate, "estimated trajectory")->required();
  rpe->add_option("--unit", a.unit, "step unit: frames, m, s")
      ->check(CLI::IsMember({"frames", "m", "s"}))
      ->capture_default_str();
  rpe->add_option("--delta", a.delta, "step in that unit")->capture_default_str();
  addCommon(rpe, a, a.max_dt);
  rpe->callback([&exit_code] {
    RpeOptions o;
    o.unit = a.unit == "frames" ? RpeUnit::Frames
             : a.unit == "m"    ? RpeUnit::Meters
                                : RpeUnit::Seconds;
    o.delta = a.delta;
    o.association.max_time_diff = a.max_dt;
    auto r = computeRpe(read(a.reference, a.ref_format), read(a.estimate, a.est_format), o);
    emit(a, toMarkdown(r), toJson(r));
    exit_code = kOk;
  });

  auto* rel = eval->add_subcommand(
      "relations", "Kuemmerle et al. relation metric, E = relation^-1 * (est(t1)^-1 * est(t2))");
  rel->footer(
      "Relations from a .relations file (t1 t2 x y z roll pitch yaw) or built from a reference "
      "trajectory. Each relation's stamps must name estimate poses (within --max-dt); the output "
      "counts the relations used and why the others were not. Reported: mean and std of |t(E)| "
      "[m], |angle(E)| [deg] and of their squares (docs/evaluation.md).");
  rel->add_option("ESTIMATE", a.estimate, "estimated trajectory")->required();
  auto* rf = rel->add_option("--relations", a.relations_file,
                             "relations file: t1 t2 x y z roll pitch yaw");
  auto* rr = rel->add_option("--reference", a.reference,
                             "reference trajectory to build relations from (all pairs within "
                             "--max-distance, plus consecutive pairs)");
  rf->excludes(rr);
  rel->add_option("--max-distance", a.max_distance, "pairs closer than this [m]")
      ->capture_default_str();
  addCommon(rel, a, a.relation_max_dt,
            "max |relation stamp - estimate stamp| [s]; keep it below the scan period");
  rel->callback([&exit_code] {
    std::vector<Relation> relations;
    if (!a.relations_file.empty())
      relations = readRelations(a.relations_file);
    else if (!a.reference.empty())
      relations = relationsFromTrajectory(read(a.reference, a.ref_format), a.max_distance);
    else
      throw InputError("eval relations needs --relations FILE or --reference TRAJECTORY");
    RelationOptions o;
    o.max_time_diff = a.relation_max_dt;
    auto r = evaluateRelations(read(a.estimate, a.est_format), relations, o);
    emit(a, toMarkdown(r), toJson(r));
    exit_code = kOk;
  });

  auto* cr = eval->add_subcommand(
      "crispness",
      "Map crispness: mean distance of each scan point to points of scans taken "
      "at least --min-gap scans apart, within --radius, and coverage: the share of points "
      "that have such a neighbour (no ground truth needed)");
  cr->add_option("LOG", a.log, "the log the trajectory was estimated from (CARMEN or ROS bag)")
      ->required();
  cr->add_option("TRAJECTORY", a.estimate, "trajectory to place the scans with")->required();
  cr->add_option("--laser", a.laser, "raw laser entry of the source")->capture_default_str();
  cr->add_option("--source", a.source_type, "source type reading LOG (default: by extension)");
  cr->add_option("--min-gap", a.min_gap, "min index gap between scans")->capture_default_str();
  cr->add_option("--max-gap", a.max_gap,
                 "max index gap between scans (0: none; a small window scores local consistency)")
      ->capture_default_str();
  cr->add_option("--radius", a.radius, "neighbour radius [m]")->capture_default_str();
  cr->add_option("--max-range", a.max_range, "ignore beams longer than this [m] (0: all)")
      ->capture_default_str();
  addCommon(cr, a, a.max_dt);
  cr->callback([&exit_code] {
    Trajectory traj = read(a.estimate, a.est_format);
    auto scans = scansFromLog(a, traj);
    CrispnessOptions o;
    o.min_index_gap = a.min_gap;
    o.max_index_gap = a.max_gap;
    o.radius = a.radius;
    auto r = computeCrispness(scans, o);
    emit(a, toMarkdown(r), toJson(r));
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
