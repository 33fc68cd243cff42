#include "render/run_pictures.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "plugslam/errors.h"
#include "plugslam/eval/rpe.h"
#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/graph_io.h"
#include "plugslam/solver/variable.h"
#include "plugslam/yaml_load.h"

namespace plugslam::runtime::render {

namespace fs = std::filesystem;

namespace {

const Rgb kEstimate{31, 119, 180};
const Rgb kReference{255, 127, 14};
const Rgb kLoop{214, 39, 40};
const Rgb kNode{23, 60, 110};
const Rgb kStart{44, 160, 44};
constexpr int kLeft = 80, kRight = 24, kTop = 64, kBottom = 64;

// P5 (binary) or P2 (ASCII) PGM with maxval <= 255, as map_server writes and reads them.
GreyRaster readPgm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read map image '" + path + "'");
  auto token = [&]() {
    std::string t;
    char c;
    while (in.get(c)) {
      if (c == '#') {
        std::string rest;
        std::getline(in, rest);
      } else if (!std::isspace(static_cast<unsigned char>(c))) {
        t += c;
        break;
      }
    }
    while (in.get(c) && !std::isspace(static_cast<unsigned char>(c))) t += c;
    return t;
  };
  const std::string magic = token();
  if (magic != "P5" && magic != "P2")
    throw InputError("map image '" + path + "': expected a PGM (P5 or P2), got '" + magic + "'");
  GreyRaster r;
  int maxval = 0;
  try {
    r.width = std::stoi(token());
    r.height = std::stoi(token());
    maxval = std::stoi(token());
  } catch (const std::exception&) {
    throw InputError("map image '" + path + "': malformed PGM header");
  }
  if (r.width <= 0 || r.height <= 0 || maxval <= 0 || maxval > 255 ||
      static_cast<long long>(r.width) * r.height > (1LL << 28))
    throw InputError(fmt::format("map image '{}': unsupported size {}x{} or maxval {}", path,
                                 r.width, r.height, maxval));
  r.pixels.resize(static_cast<size_t>(r.width) * r.height);
  if (magic == "P5") {
    in.read(reinterpret_cast<char*>(r.pixels.data()),
            static_cast<std::streamsize>(r.pixels.size()));
    if (in.gcount() != static_cast<std::streamsize>(r.pixels.size()))
      throw InputError("map image '" + path + "': truncated pixel data");
  } else {
    for (auto& p : r.pixels) {
      int v = 0;
      if (!(in >> v)) throw InputError("map image '" + path + "': truncated pixel data");
      p = static_cast<uint8_t>(std::clamp(v, 0, maxval));
    }
  }
  if (maxval != 255)
    for (auto& p : r.pixels) p = static_cast<uint8_t>(p * 255 / maxval);
  return r;
}

// map.yaml (ROS map_server): image, resolution, origin [x, y, yaw]; yaw must be 0 to be drawn.
std::optional<GreyRaster> readMap(const fs::path& yaml_path) {
  if (!fs::exists(yaml_path)) return std::nullopt;
  YAML::Node y;
  try {
    y = loadYamlFile(yaml_path.string());
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}:{}: {}", yaml_path.string(), e.mark.line + 1, e.msg));
  }
  if (!y["image"] || !y["resolution"] || !y["origin"] || y["origin"].size() < 2)
    throw InputError("'" + yaml_path.string() + "': expected image, resolution and origin");
  fs::path image = y["image"].as<std::string>();
  if (image.is_relative()) image = yaml_path.parent_path() / image;
  GreyRaster r;
  if (image.extension() == ".png") {
    const RgbImage c = readPng(image.string());
    r.width = c.width;
    r.height = c.height;
    for (int row = 0; row < c.height; ++row)
      for (int col = 0; col < c.width; ++col) r.pixels.push_back(c.at(col, row).r);
  } else {
    r = readPgm(image.string());
  }
  if (y["negate"] && y["negate"].as<int>(0) != 0)
    for (auto& p : r.pixels) p = static_cast<uint8_t>(255 - p);
  r.resolution = y["resolution"].as<double>();
  r.x0 = y["origin"][0].as<double>();
  r.y0 = y["origin"][1].as<double>();
  if (!(r.resolution > 0))
    throw InputError("'" + yaml_path.string() + "': resolution must be positive");
  return r;
}

bool isPlanar(const Trajectory& t) {
  for (const auto& p : t) {
    if (std::abs(p.pose.translation().z()) > 1e-6) return false;
    if (std::abs(p.pose.linear()(2, 2) - 1.0) > 1e-6) return false;
  }
  return true;
}

std::vector<Eigen::Vector2d> topView(const Trajectory& t) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(t.size());
  for (const auto& p : t) out.push_back(p.pose.translation().head<2>());
  return out;
}

Alignment alignmentOf(const RunData& run, const RenderOptions& o) {
  if (o.alignment) return *o.alignment;
  return run.dimension == 2 ? Alignment::SE2 : Alignment::SE3;
}

std::string lengthText(double m) {
  return m >= 1000 ? fmt::format("{:.2f} km", m / 1000) : fmt::format("{:.1f} m", m);
}

// A panel for y-values from 0 to their largest, x from the data.
Panel plotPanel(int x, int y, int w, int h, const std::vector<Eigen::Vector2d>& pts) {
  Panel p;
  p.x = x;
  p.y = y;
  p.width = w;
  p.height = h;
  double x0 = 1e300, x1 = -1e300, y1 = 0;
  for (const auto& q : pts) {
    x0 = std::min(x0, q.x());
    x1 = std::max(x1, q.x());
    y1 = std::max(y1, q.y());
  }
  if (!(x1 > x0)) x1 = x0 + 1;
  p.x_min = x0;
  p.x_max = x1;
  p.y_min = 0;
  p.y_max = y1 > 0 ? y1 : 1;
  return p;
}

}  // namespace

RunData loadRun(const std::string& dir, const RenderOptions& options) {
  RunData run;
  run.dir = dir;
  const fs::path d(dir);
  if (!fs::is_directory(d)) throw InputError("'" + dir + "' is not a folder");
  const fs::path est =
      options.estimate_file.empty() ? d / "trajectory.tum" : fs::path(options.estimate_file);
  if (!fs::exists(est))
    throw InputError("no trajectory in '" + dir + "': expected " + est.string() +
                     " (what `plugslam run -o DIR` writes)");
  run.estimate = readTrajectory(est.string());
  if (run.estimate.empty()) throw InputError("'" + est.string() + "' holds no pose");

  fs::path ref = options.reference_file;
  if (ref.empty())
    for (const char* name : {"reference.tum", "ground_truth.tum"})
      if (fs::exists(d / name)) {
        ref = d / name;
        break;
      }
  if (!ref.empty()) {
    if (!fs::exists(ref)) throw InputError("reference '" + ref.string() + "' does not exist");
    run.reference = readTrajectory(ref.string());
    run.reference_path = ref.string();
  }

  run.dimension = isPlanar(run.estimate) ? 2 : 3;
  const fs::path graph_path = d / "graph.g2o";
  if (fs::exists(graph_path)) {
    FactorGraph graph;
    const GraphFileInfo info = readGraphFile(graph_path.string(), graph);
    run.dimension = info.dimension;
    for (const Variable* v : graph.variables()) {
      if (const auto* a = dynamic_cast<const VariableSE2*>(v))
        run.nodes.push_back(a->estimate().translation());
      else if (const auto* b = dynamic_cast<const VariableSE3*>(v))
        run.nodes.push_back(b->estimate().translation().head<2>());
    }
    // Local maps are numbered in order and odometry links consecutive ones: any other pose-pose
    // edge closes a loop.
    auto position = [](const Variable* v) -> std::optional<Eigen::Vector2d> {
      if (const auto* a = dynamic_cast<const VariableSE2*>(v)) return a->estimate().translation();
      if (const auto* b = dynamic_cast<const VariableSE3*>(v))
        return Eigen::Vector2d(b->estimate().translation().head<2>());
      return std::nullopt;
    };
    for (const auto& f : graph.factors()) {
      if (f->numVariables() != 2) continue;
      const Variable* a = f->variable(0);
      const Variable* b = f->variable(1);
      if (std::abs(a->id() - b->id()) <= 1) continue;
      const auto pa = position(a), pb = position(b);
      if (!pa || !pb) continue;
      run.loop_ends.push_back(*pa);
      run.loop_ends.push_back(*pb);
    }
  }
  run.map = readMap(d / "map.yaml");
  // A merged run: its sessions' trajectories in the merged frame and the links between them.
  const fs::path merge = d / "merge.json";
  if (fs::exists(merge)) {
    nlohmann::json j;
    try {
      std::ifstream in(merge.string());
      j = nlohmann::json::parse(in);
      for (const auto& s : j.at("sessions")) {
        if (!s.at("joined").get<bool>() || s.at("trajectory").is_null()) continue;
        const fs::path t = d / fs::path(s.at("trajectory").get<std::string>()).filename();
        // Named by its folder (a run's saved session is RUN/session: the run's folder).
        fs::path name = fs::path(s.at("session").get<std::string>());
        if (name.filename() == "session" && name.has_parent_path()) name = name.parent_path();
        if (fs::exists(t)) run.sessions.emplace_back(name.filename().string(), readTrajectory(t.string()));
      }
      for (const auto& l : j.at("link_list")) {
        const auto from = l.at("from").get<size_t>(), to = l.at("to").get<size_t>();
        if (from >= run.nodes.size() || to >= run.nodes.size()) continue;
        run.link_ends.push_back(run.nodes[from]);
        run.link_ends.push_back(run.nodes[to]);
      }
    } catch (const std::exception& e) {
      throw InputError("'" + merge.string() + "' is not a merge report: " + e.what());
    }
  }
  return run;
}

Figure mapFigure(const RunData& run, const RenderOptions& o) {
  std::vector<Eigen::Vector2d> est = topView(run.estimate), ref;
  std::string ate_note;
  if (run.reference) {
    // The reference is drawn in the estimate's frame (the map's), moved by the inverse of the
    // alignment that evaluation uses.
    try {
      AteOptions ao;
      ao.alignment = alignmentOf(run, o);
      const AteResult ate = computeAte(*run.reference, run.estimate, ao);
      const SimilarityTransform& s = ate.transform;
      for (const auto& p : *run.reference) {
        const Eigen::Vector3d q =
            s.rotation.transpose() * (p.pose.translation() - s.translation) / s.scale;
        ref.push_back(q.head<2>());
      }
      ate_note = fmt::format("ATE RMSE {:.3f} m ({} alignment)", ate.translation.rmse,
                             toString(ao.alignment));
    } catch (const InputError& e) {
      ate_note = std::string("reference not drawn: ") + e.what();
    }
  }
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  auto grow = [&](const Eigen::Vector2d& p) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  };
  for (const auto& p : est) grow(p);
  for (const auto& p : ref) grow(p);
  if (run.map) {
    const GreyRaster& m = *run.map;
    grow({m.x0, m.y0});
    grow({m.x0 + m.width * m.resolution, m.y0 + m.height * m.resolution});
  } else {
    const double pad = 0.04 * std::max({x1 - x0, y1 - y0, 1.0});
    x0 -= pad, x1 += pad, y0 -= pad, y1 += pad;
  }
  const double dx = std::max(x1 - x0, 1e-3), dy = std::max(y1 - y0, 1e-3);
  const int plot = std::max(200, o.width - kLeft - kRight);
  // Equal axes; a tall scene is limited to 1.4 times the width rather than made huge.
  const double scale = std::min(plot / dx, 1.4 * plot / dy);
  Figure f;
  Panel p;
  p.x = kLeft;
  p.y = kTop;
  p.width = std::max(1, static_cast<int>(std::lround(dx * scale)));
  p.height = std::max(1, static_cast<int>(std::lround(dy * scale)));
  p.x_min = x0;
  p.x_max = x0 + p.width / scale;
  p.y_max = y1;
  p.y_min = y1 - p.height / scale;
  p.x_label = "x [m]";
  p.y_label = "y [m]";
  p.background = run.map;
  f.width = p.x + p.width + kRight;
  f.height = p.y + p.height + kBottom;
  const double path = run.estimate.pathLength();
  f.title = fmt::format(
      "{}: {} poses, {}, {} local maps, {} loop closures",
      fs::path(run.dir).filename().string().empty() ? run.dir
                                                    : fs::path(run.dir).filename().string(),
      run.estimate.size(), lengthText(path), run.nodes.size(), run.loop_ends.size() / 2);
  if (!ate_note.empty()) p.notes.push_back(ate_note);
  if (!run.loop_ends.empty()) {
    // Thousands of closures would paint the map over: fainter the more there are.
    const double alpha = std::clamp(10.0 / std::sqrt(run.loop_ends.size() / 2.0), 0.12, 0.6);
    p.series.push_back(
        {"loop closures", "loops", Series::Kind::Segments, kLoop, 1.0, alpha, run.loop_ends});
  }
  if (!ref.empty())
    p.series.push_back(
        {run.reference_path.empty()
             ? "reference"
             : "reference (" + fs::path(run.reference_path).filename().string() + ")",
         "reference", Series::Kind::Line, kReference, 2.0, 0.9, ref});
  if (run.sessions.empty()) {
    p.series.push_back({"estimate", "estimate", Series::Kind::Line, kEstimate, 2.0, 1.0, est});
  } else {
    // A merged run: one colour per session, and the links that joined them.
    static const Rgb palette[] = {kEstimate, {44, 160, 44}, {148, 103, 189}, {140, 86, 75},
                                  {227, 119, 194}, {23, 190, 207}};
    if (!run.link_ends.empty()) {
      const double alpha = std::clamp(10.0 / std::sqrt(run.link_ends.size() / 2.0), 0.15, 0.8);
      p.series.push_back({"links across sessions", "links", Series::Kind::Segments, kReference,
                          1.5, alpha, run.link_ends});
    }
    for (size_t i = 0; i < run.sessions.size(); ++i)
      p.series.push_back({run.sessions[i].first, "session", Series::Kind::Line,
                          palette[i % (sizeof(palette) / sizeof(palette[0]))], 2.0, 1.0,
                          topView(run.sessions[i].second)});
  }
  if (!run.nodes.empty())
    p.series.push_back({"", "nodes", Series::Kind::Points, kNode, 3.0, 0.8, run.nodes});
  p.series.push_back({"", "start", Series::Kind::Points, kStart, 9.0, 1.0, {est.front()}});
  f.panels.push_back(std::move(p));
  return f;
}

Figure errorFigure(const RunData& run, const RenderOptions& o) {
  if (!run.reference) throw InputError("no reference trajectory in '" + run.dir + "'");
  const Trajectory& ref = *run.reference;
  AteOptions ao;
  ao.alignment = alignmentOf(run, o);
  const AteResult ate = computeAte(ref, run.estimate, ao);
  const std::vector<double> dist = ref.cumulativeDistances();
  const double t0 = ref[ate.pairs.front().ref].t;
  std::vector<Eigen::Vector2d> by_time, by_dist;
  for (size_t k = 0; k < ate.pairs.size(); ++k) {
    by_time.emplace_back(ref[ate.pairs[k].ref].t - t0, ate.translation_errors[k]);
    by_dist.emplace_back(dist[ate.pairs[k].ref], ate.translation_errors[k]);
  }
  const int w = std::max(300, o.width - kLeft - kRight), h = 200, gap = 110;
  Figure f;
  f.width = kLeft + w + kRight;
  f.title = fmt::format("{}: errors against {}", fs::path(run.dir).filename().string(),
                        fs::path(run.reference_path).filename().string());
  int y = kTop;
  auto add = [&](Panel p, const std::string& title, const std::string& xl, const std::string& yl,
                 const std::string& cls, const std::vector<Eigen::Vector2d>& pts,
                 std::vector<std::string> notes) {
    p.title = title;
    p.x_label = xl;
    p.y_label = yl;
    p.notes = std::move(notes);
    // Head room above the largest value for the notes, so they never hide the curve.
    const double reserved = (p.notes.size() * (textLineHeight() + 6) + 14.0) / h;
    p.y_max /= 1.0 - std::min(reserved, 0.5);
    p.series.push_back({"", cls, Series::Kind::Line, kEstimate, 1.5, 1.0, pts});
    f.panels.push_back(std::move(p));
    y += h + gap;
  };
  const std::vector<std::string> ate_notes{
      fmt::format("RMSE {:.3f} m, mean {:.3f} m, max {:.3f} m", ate.translation.rmse,
                  ate.translation.mean, ate.translation.max),
      fmt::format("{} poses, {} alignment", ate.pairs.size(), toString(ao.alignment))};
  add(plotPanel(kLeft, y, w, h, by_time), "ATE per pose over time", "time [s]", "ATE [m]",
      "ate-time", by_time, ate_notes);
  add(plotPanel(kLeft, y, w, h, by_dist), "ATE per pose over distance travelled",
      "distance travelled along the reference [m]", "ATE [m]", "ate-distance", by_dist, ate_notes);
  RpeOptions ro;
  ro.unit = RpeUnit::Meters;
  ro.delta = o.rpe_delta;
  try {
    const RpeResult rpe = computeRpe(ref, run.estimate, ro);
    std::vector<Eigen::Vector2d> trans, rot;
    for (const RpeSegment& s : rpe.segments) {
      trans.emplace_back(dist[s.first.ref], s.translation);
      rot.emplace_back(dist[s.first.ref], s.rotation_deg);
    }
    add(plotPanel(kLeft, y, w, h, trans),
        fmt::format("RPE over {:g} m segments: translation", o.rpe_delta),
        "distance travelled at the segment's start [m]", "RPE [m]", "rpe-translation", trans,
        {fmt::format("RMSE {:.3f} m, max {:.3f} m, {} segments", rpe.translation.rmse,
                     rpe.translation.max, rpe.pairs)});
    add(plotPanel(kLeft, y, w, h, rot),
        fmt::format("RPE over {:g} m segments: rotation", o.rpe_delta),
        "distance travelled at the segment's start [m]", "RPE [deg]", "rpe-rotation", rot,
        {fmt::format("RMSE {:.2f} deg, max {:.2f} deg", rpe.rotation_deg.rmse,
                     rpe.rotation_deg.max)});
  } catch (const InputError& e) {
    f.panels.back().notes.push_back(std::string("no RPE: ") + e.what());
  }
  f.height = y - gap + kBottom;
  return f;
}

std::vector<std::string> renderRun(const std::string& dir, const std::string& out_dir,
                                   const RenderOptions& options) {
  const RunData run = loadRun(dir, options);
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw InputError("cannot create '" + out_dir + "': " + ec.message());
  std::vector<std::string> written;
  auto emit = [&](const Figure& f, const std::string& stem) {
    for (const std::string& format : options.formats) {
      const std::string path = (fs::path(out_dir) / (stem + "." + format)).string();
      writeFigure(f, path);
      written.push_back(path);
    }
  };
  emit(mapFigure(run, options), "render_map");
  if (run.reference) {
    try {
      emit(errorFigure(run, options), "render_errors");
    } catch (const InputError& e) {
      spdlog::warn("no error plots: {}", e.what());
    }
  } else {
    spdlog::info("no reference.tum or ground_truth.tum in '{}': no error plots", dir);
  }
  return written;
}

}  // namespace plugslam::runtime::render
