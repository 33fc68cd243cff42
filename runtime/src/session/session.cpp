#include "session/session.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <boost/filesystem.hpp>
#include <fstream>
#include <sstream>

#include "plugslam/archive.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/version.h"
#include "plugslam/yaml_load.h"

namespace plugslam::runtime {

namespace fs = boost::filesystem;

namespace {

// A map's dimension is an int in memory and 64 bits in the file. One out of range loads as 0,
// which loadMap rejects once every field is read.
void dimension(OutArchive& ar, const LocalMap& m) {
  ar.field("dimension", static_cast<std::int64_t>(m.dimension));
}
void dimension(InArchive& ar, LocalMap& m) {
  std::int64_t dim = 0;
  ar.field("dimension", dim);
  m.dimension = dim == 2 || dim == 3 ? static_cast<int>(dim) : 0;
}

// One field list per type serves both directions, as in sensor_data.cpp.
template <class Ar, class M>
void mapFields(Ar& ar, M& m) {
  ar.field("id", m.id);
  dimension(ar, m);
  ar.field("origin", m.origin).field("scene", m.scene);
  ar.field("first_seq", m.first_seq).field("last_seq", m.last_seq);
  ar.field("first_stamp", m.first_stamp).field("last_stamp", m.last_stamp);
  ar.field("previous", m.previous).field("relative", m.relative);
  ar.field("information", m.information);
}

void saveMap(OutArchive& ar, const LocalMap& m) {
  ar.beginObject();
  mapFields(ar, m);
  ar.endObject();
}

void loadMap(InArchive& ar, LocalMap& m) {
  ar.beginObject();
  mapFields(ar, m);
  if (m.dimension == 0) ar.fail("a local map's dimension must be 2 or 3");
  ar.endObject();
}

template <class Ar, class E>
void edgeFields(Ar& ar, E& e) {
  ar.beginObject();
  ar.field("from", e.from).field("to", e.to).field("relative", e.relative);
  ar.field("information", e.information).field("loop", e.loop);
  ar.endObject();
}

void writeText(const std::string& path, const std::string& text) {
  writeFileAtomically(path, [&](std::ostream& out) { out << text; });
}

std::string readText(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read " + what + " '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

std::vector<std::shared_ptr<LocalMap>> copyMaps(
    const std::vector<std::shared_ptr<LocalMap>>& maps) {
  std::vector<std::shared_ptr<LocalMap>> out;
  out.reserve(maps.size());
  for (const auto& m : maps) out.push_back(std::make_shared<LocalMap>(*m));
  return out;
}

SessionSummary saveSession(const std::string& dir, const std::string& config_yaml,
                           Pipeline& pipeline) {
  const RunResult result = pipeline.result();
  const int dimension = pipeline.tracker            ? pipeline.tracker->dimension()
                        : result.local_maps.empty() ? 0
                                                    : result.local_maps.front()->dimension;
  return saveSession(dir, config_yaml, result, dimension, pipeline.graph.get());
}

SessionSummary saveSession(const std::string& dir, const std::string& config_yaml,
                           const RunResult& result, int dimension, GraphBackend* graph) {
  boost::system::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError("cannot create session folder '" + dir + "': " + ec.message());
  const fs::path d(dir);
  SessionSummary summary;
  summary.maps = result.local_maps.size();
  summary.edges = result.edges.size();
  summary.poses = result.trajectory.size();
  writeText((d / "config.yaml").string(), config_yaml);
  writeTumTrajectory(result.trajectory, (d / "trajectory.tum").string());
  saveArchiveFile((d / "maps.bin").string(), ArchiveFormat::kBinary, [&](OutArchive& ar) {
    ar.beginObject();
    ar.field("format_version", static_cast<std::int64_t>(kSessionFormatVersion));
    ar.field("dimension", static_cast<std::int64_t>(dimension));
    ar.key("maps");
    ar.beginArray(result.local_maps.size());
    for (const auto& m : result.local_maps) saveMap(ar, *m);
    ar.endArray();
    ar.key("edges");
    ar.beginArray(result.edges.size());
    for (const auto& e : result.edges) edgeFields(ar, e);
    ar.endArray();
    ar.endObject();
  });
  if (graph) {
    for (const auto& a : graph->actions()) {
      if (a.name != "save_graph") continue;
      graph->invoke("save_graph", {(d / "graph.g2o").string()});
      summary.graph_file = true;
    }
  }
  // Written last: a folder without it (a save cut short) is not a session.
  writeText(
      (d / "session.yaml").string(),
      fmt::format("# plugslam session (docs/shell.md)\n"
                  "plugslam_session: {}\n"
                  "written_by: plugslam {}\n"
                  "dimension: {}\n"
                  "maps: {}\n"
                  "edges: {}\n"
                  "poses: {}\n"
                  "files: {{config: config.yaml, maps: maps.bin, trajectory: trajectory.tum{}}}\n",
                  kSessionFormatVersion, PLUGSLAM_VERSION_STRING, dimension, summary.maps,
                  summary.edges, summary.poses, summary.graph_file ? ", graph: graph.g2o" : ""));
  return summary;
}

SessionManifest readSessionManifest(const std::string& dir) {
  const fs::path d(dir);
  const std::string manifest_path = (d / "session.yaml").string();
  if (!fs::is_directory(d)) throw InputError("session folder '" + dir + "' does not exist");
  if (!fs::exists(manifest_path))
    throw InputError("'" + dir + "' is not a plugslam session: it has no session.yaml");
  YAML::Node root;
  try {
    root = loadYamlFile(manifest_path);
  } catch (const YAML::Exception& e) {
    throw ParseError(manifest_path, e.mark.line + 1, "invalid YAML: " + e.msg);
  }
  SessionManifest m;
  m.dir = dir;
  if (!root.IsMap() || !root["plugslam_session"] || !root["plugslam_session"].IsScalar())
    throw ParseError(manifest_path, 1, "expected 'plugslam_session: <format version>'");
  try {
    m.format_version = root["plugslam_session"].as<int>();
    m.dimension = root["dimension"] ? root["dimension"].as<int>() : 0;
    m.maps = root["maps"] ? root["maps"].as<size_t>() : 0;
    m.edges = root["edges"] ? root["edges"].as<size_t>() : 0;
  } catch (const YAML::Exception& e) {
    throw ParseError(manifest_path, e.mark.line + 1, "expected integers: " + e.msg);
  }
  if (m.format_version != kSessionFormatVersion) {
    std::string by = root["written_by"] && root["written_by"].IsScalar()
                         ? " (written by " + root["written_by"].Scalar() + ")"
                         : "";
    throw InputError("session '" + dir + "' has format version " +
                     std::to_string(m.format_version) + by + ", but plugslam " +
                     PLUGSLAM_VERSION_STRING + " reads session format " +
                     std::to_string(kSessionFormatVersion) +
                     " only and has no migration for it; re-create the session with this build");
  }
  m.config_path = (d / "config.yaml").string();
  m.config_text = readText(m.config_path, "session config");
  return m;
}

SessionMaps loadSessionMaps(const SessionManifest& manifest) {
  SessionMaps out;
  const std::string path = (fs::path(manifest.dir) / "maps.bin").string();
  if (!fs::exists(path)) throw InputError("session '" + manifest.dir + "' has no maps.bin");
  loadArchiveFile(path, [&](InArchive& ar) {
    ar.beginObject();
    std::int64_t version = 0, dimension = 0;
    ar.field("format_version", version).field("dimension", dimension);
    if (version != kSessionFormatVersion)
      ar.fail("maps.bin has session format " + std::to_string(version) + ", expected " +
              std::to_string(kSessionFormatVersion));
    ar.key("maps");
    const size_t n = ar.beginArray();
    for (size_t i = 0; i < n; ++i) {
      auto m = std::make_shared<LocalMap>();
      loadMap(ar, *m);
      if (m->id != static_cast<int64_t>(i)) ar.fail("local maps must be stored by id 0, 1, 2, ...");
      out.maps.push_back(std::move(m));
    }
    ar.endArray();
    ar.key("edges");
    const size_t k = ar.beginArray();
    for (size_t i = 0; i < k; ++i) {
      GraphEdge e;
      edgeFields(ar, e);
      if (e.from < 0 || e.to < 0 || e.from >= static_cast<int64_t>(n) ||
          e.to >= static_cast<int64_t>(n))
        ar.fail("edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                " names a map that is not stored");
      out.edges.push_back(std::move(e));
    }
    ar.endArray();
    ar.endObject();
  });
  return out;
}

}  // namespace plugslam::runtime
