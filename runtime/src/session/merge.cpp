#include "session/merge.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/filesystem.hpp>
#include <chrono>
#include <nlohmann/json.hpp>
#include <numeric>
#include <set>
#include <tuple>

#include "config_builder.h"
#include "plugin_manager.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/trajectory.h"
#include "run_config.h"
#include "session/session.h"

namespace plugslam::runtime {

namespace fs = boost::filesystem;

namespace {

// The scene entries a session's maps hold (name and value type), from its first map.
std::vector<std::pair<std::string, std::string>> cuesOf(const SessionMaps& s) {
  std::vector<std::pair<std::string, std::string>> cues;
  if (s.maps.empty()) return cues;
  for (const std::string& n : s.maps.front()->scene.names())
    cues.emplace_back(n, s.maps.front()->scene.at(n).type().name());
  std::sort(cues.begin(), cues.end());
  return cues;
}

std::string cueNames(const std::vector<std::pair<std::string, std::string>>& cues) {
  std::string out;
  for (const auto& c : cues) out += (out.empty() ? "" : ", ") + c.first;
  return out.empty() ? "none" : out;
}

// Poses of a session's trajectory re-expressed in the merged frame: each pose moves with the
// local map whose frames span its stamp (the nearest in time when none does).
std::vector<StampedPose> reexpressed(const Trajectory& trajectory,
                                     const std::vector<std::shared_ptr<LocalMap>>& saved,
                                     const std::vector<std::shared_ptr<const LocalMap>>& merged,
                                     int64_t first_id) {
  std::vector<StampedPose> out;
  if (saved.empty()) return out;
  for (const StampedPose& p : trajectory) {
    size_t best = 0;
    double gap = 1e300;
    for (size_t i = 0; i < saved.size(); ++i) {
      const LocalMap& m = *saved[i];
      const double d = p.t < m.first_stamp ? m.first_stamp - p.t
                       : p.t > m.last_stamp ? p.t - m.last_stamp
                                            : 0.0;
      if (d < gap) {
        gap = d;
        best = i;
      }
      if (d == 0) break;
    }
    const LocalMap& now = *merged[static_cast<size_t>(first_id) + best];
    out.push_back({p.t, now.origin * saved[best]->origin.inverse() * p.pose});
  }
  return out;
}

struct Loaded {
  SessionManifest manifest;
  SessionMaps maps;
  Trajectory trajectory;
};

// Restores `inputs` (indices into `loaded`) into the pipeline of `run`, one component each,
// and searches loops from every map after the first session's. Returns each input's first id.
std::vector<int64_t> restoreAndSearch(RunConfig& run, const std::vector<Loaded>& loaded,
                                      const std::vector<size_t>& inputs) {
  std::vector<std::shared_ptr<LocalMap>> maps;
  std::vector<GraphEdge> edges;
  std::vector<int64_t> first_ids;
  for (size_t k : inputs) {
    const auto offset = static_cast<int64_t>(maps.size());
    first_ids.push_back(offset);
    // Copies: the loaded maps keep their saved origins for re-expressing the trajectories.
    for (const auto& m : copyMaps(loaded[k].maps.maps)) {
      m->id += offset;
      if (m->previous >= 0) m->previous += offset;
      maps.push_back(m);
    }
    for (GraphEdge e : loaded[k].maps.edges) {
      e.from += offset;
      e.to += offset;
      edges.push_back(e);
    }
  }
  // Odometry edges first, then loops, as a back-end's edges() gives them.
  std::stable_partition(edges.begin(), edges.end(), [](const GraphEdge& e) { return !e.loop; });
  run.pipeline->restoreSession(maps, edges, false);
  if (first_ids.size() > 1) run.pipeline->graph->searchRestored(first_ids[1]);
  return first_ids;
}

}  // namespace

MergeReport mergeSessions(const MergeOptions& options, PluginManager& plugins) {
  const auto start = std::chrono::steady_clock::now();
  if (options.sessions.size() < 2)
    throw InputError("merge needs at least two sessions, got " +
                     std::to_string(options.sessions.size()));
  std::vector<Loaded> loaded;
  for (const auto& dir : options.sessions) loaded.push_back({readSessionManifest(dir), {}, {}});
  const SessionManifest& first = loaded.front().manifest;
  for (const auto& l : loaded)
    if (l.manifest.dimension != first.dimension)
      throw InputError(fmt::format("session '{}' is {}D but '{}' is {}D: only sessions of one "
                                   "dimension merge",
                                   l.manifest.dir, l.manifest.dimension, first.dir,
                                   first.dimension));

  // The first session's config, its graph told that the sessions' relative poses are unknown.
  const auto build = [&]() {
    ConfigDocument doc = loadConfigText(first.config_text, first.config_path);
    for (const auto& s : options.sets) applyOverride(doc, s);
    applyOverride(doc, "pipeline.graph.join_by_estimate=false");
    auto run = buildRun(doc, plugins);
    if (!run->pipeline->tracker || !run->pipeline->graph)
      throw InputError("session '" + first.dir +
                       "': its config has no tracker and graph back-end to merge maps with");
    return std::make_pair(run, resolvedYaml(doc));
  };
  std::shared_ptr<RunConfig> run;
  std::string config_yaml;
  std::tie(run, config_yaml) = build();

  // After buildRun: the config's plugins register the value types the scenes hold.
  for (auto& l : loaded) {
    try {
      l.maps = loadSessionMaps(l.manifest);
    } catch (const InputError& e) {
      if (&l == &loaded.front()) throw;
      throw InputError(fmt::format("session '{}' cannot be read with the plugins of '{}' (its "
                                   "maps hold what they do not know): sessions of different "
                                   "sensors or configs do not merge ({})",
                                   l.manifest.dir, first.dir, e.what()));
    }
    const std::string tum = (fs::path(l.manifest.dir) / "trajectory.tum").string();
    if (fs::exists(tum)) l.trajectory = readTumTrajectory(tum);
  }
  const auto cues = cuesOf(loaded.front().maps);
  for (const auto& l : loaded)
    if (cuesOf(l.maps) != cues)
      throw InputError(fmt::format(
          "session '{}' holds the cues {} but '{}' holds {}: sessions of different sensors or "
          "configs do not merge",
          l.manifest.dir, cueNames(cuesOf(l.maps)), first.dir, cueNames(cues)));

  MergeReport report;
  for (const auto& l : loaded) {
    MergedInput in;
    in.dir = l.manifest.dir;
    in.maps = l.maps.maps.size();
    report.inputs.push_back(in);
  }
  std::vector<size_t> inputs(loaded.size());
  std::iota(inputs.begin(), inputs.end(), 0);
  std::vector<int64_t> first_ids = restoreAndSearch(*run, loaded, inputs);

  // Which sessions the loops joined to the first one.
  const auto joinedInputs = [&](const std::vector<size_t>& in, const std::vector<int64_t>& ids) {
    const auto edges = run->pipeline->graph->edges();
    size_t total = 0;
    for (size_t k : in) total += loaded[k].maps.maps.size();
    const auto components = graphComponents(total, edges);
    std::vector<size_t> out;
    for (size_t i = 0; i < in.size(); ++i)
      if (components[static_cast<size_t>(ids[i])] == components[0]) out.push_back(in[i]);
    return out;
  };
  std::vector<size_t> joined = joinedInputs(inputs, first_ids);
  if (joined.size() < 2) {
    for (size_t k = 1; k < loaded.size(); ++k)
      spdlog::warn("session '{}' shares no place with '{}' that place recognition found: not "
                   "merged",
                   loaded[k].manifest.dir, first.dir);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return report;
  }
  if (joined.size() < inputs.size()) {
    // Sessions that stayed apart are left out: the merge is done again without them (the
    // search is deterministic, so the joined ones join alike).
    for (size_t k : inputs)
      if (std::find(joined.begin(), joined.end(), k) == joined.end())
        spdlog::warn("session '{}' shares no place with the others that place recognition "
                     "found: not merged",
                     loaded[k].manifest.dir);
    run = build().first;
    inputs = joined;
    first_ids = restoreAndSearch(*run, loaded, inputs);
    joined = joinedInputs(inputs, first_ids);
    if (joined.size() != inputs.size())
      spdlog::warn("without the sessions left out, another session did not join; it stays in "
                   "the merged graph as a component of its own");
  }
  spdlog::info("merge: final loop search and optimization over {} maps",
               run->pipeline->graph->stats().nodes);
  run->pipeline->finish();

  // Outputs: every session's trajectory in the merged frame, the config's writers over the
  // merged maps, and the merged session.
  RunResult result = run->pipeline->result();
  boost::system::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) throw InputError("cannot create output folder '" + options.out_dir + "': " + ec.message());
  std::vector<StampedPose> all, first_poses;
  std::vector<std::pair<double, double>> spans;  // each trajectory's first and last stamp
  const auto edges = result.edges;
  const auto owner = [&](int64_t id) {
    size_t i = 0;
    while (i + 1 < first_ids.size() && id >= first_ids[i + 1]) ++i;
    return i;
  };
  for (size_t i = 0; i < inputs.size(); ++i) {
    MergedInput& in = report.inputs[inputs[i]];
    in.joined = std::find(joined.begin(), joined.end(), inputs[i]) != joined.end();
    in.first_id = first_ids[i];
    const Loaded& l = loaded[inputs[i]];
    std::vector<StampedPose> poses =
        reexpressed(l.trajectory, l.maps.maps, result.local_maps, first_ids[i]);
    in.poses = poses.size();
    if (!poses.empty()) spans.emplace_back(poses.front().t, poses.back().t);
    if (i == 0) first_poses = poses;
    in.trajectory_file =
        (fs::path(options.out_dir) / fmt::format("trajectory_{}.tum", inputs[i] + 1)).string();
    writeTumTrajectory(Trajectory(poses), in.trajectory_file);
    all.insert(all.end(), poses.begin(), poses.end());
  }
  for (const auto& e : edges) {
    if (!e.loop || owner(e.from) == owner(e.to)) continue;
    ++report.links;
    MergeLink link;
    link.from = e.from;
    link.to = e.to;
    link.from_stamp = result.local_maps[static_cast<size_t>(e.from)]->first_stamp;
    link.to_stamp = result.local_maps[static_cast<size_t>(e.to)]->first_stamp;
    link.relative = e.relative;
    report.link_list.push_back(link);
    ++report.inputs[inputs[owner(e.from)]].links;
    ++report.inputs[inputs[owner(e.to)]].links;
  }
  // One trajectory of all runs, in time order, unless their times overlap (robots mapping at
  // once, simulated clocks): then it is the first session's, and each run has its own file.
  bool overlap = false;
  for (size_t i = 0; i < spans.size(); ++i)
    for (size_t k = i + 1; k < spans.size(); ++k)
      overlap = overlap ||
                (spans[i].first <= spans[k].second && spans[k].first <= spans[i].second);
  if (overlap) {
    spdlog::warn("the sessions' times overlap: trajectory.tum holds the first session's poses "
                 "only; trajectory_K.tum holds each session's");
    all = first_poses;
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });
  result.trajectory = Trajectory(std::move(all));
  for (auto& sink : run->outputs) {
    sink->begin(options.out_dir);
    sink->end(result);
  }
  saveSession((fs::path(options.out_dir) / "session").string(), config_yaml, result,
              run->pipeline->tracker->dimension(), run->pipeline->graph.get());
  report.maps = result.local_maps.size();
  report.edges = result.edges.size();
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeFileAtomically((fs::path(options.out_dir) / "merge.json").string(),
                      [&](std::ostream& out) { out << mergeReportJson(report); });
  return report;
}

std::string mergeReportJson(const MergeReport& report) {
  nlohmann::ordered_json j;
  j["maps"] = report.maps;
  j["edges"] = report.edges;
  j["links"] = report.links;
  j["seconds"] = report.seconds;
  nlohmann::ordered_json inputs = nlohmann::ordered_json::array();
  for (const auto& in : report.inputs) {
    nlohmann::ordered_json i;
    i["session"] = in.dir;
    i["maps"] = in.maps;
    i["joined"] = in.joined;
    i["first_map"] = in.first_id;
    i["links"] = in.links;
    i["poses"] = in.poses;
    i["trajectory"] = in.trajectory_file.empty() ? nlohmann::ordered_json(nullptr)
                                                 : nlohmann::ordered_json(in.trajectory_file);
    inputs.push_back(i);
  }
  j["sessions"] = inputs;
  // The links as TUM-like rows: the two maps, their origins' stamps, and the relative pose
  // (x y z qx qy qz qw), so that a reference trajectory can judge each.
  nlohmann::ordered_json links = nlohmann::ordered_json::array();
  for (const auto& l : report.link_list) {
    const Eigen::Quaterniond q(l.relative.linear());
    const Eigen::Vector3d t = l.relative.translation();
    links.push_back({{"from", l.from},
                     {"to", l.to},
                     {"from_stamp", l.from_stamp},
                     {"to_stamp", l.to_stamp},
                     {"relative", {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}}});
  }
  j["link_list"] = links;
  return j.dump(2) + "\n";
}

}  // namespace plugslam::runtime
