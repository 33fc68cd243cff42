// `plugslam render`: the pictures of a run folder, read back. A synthetic run with a known map,
// trajectory, reference and loop closure is drawn; the test then reads the PNG's pixels and the
// SVG's path coordinates and checks that each thing is drawn where it belongs (not that a file
// exists).
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "plugslam/errors.h"
#include "plugslam/trajectory.h"
#include "render/figure.h"
#include "render/image.h"
#include "render/run_pictures.h"
#include "run_command.h"
#include "temp_dir.h"
#include "test_paths.h"

namespace fs = std::filesystem;
using namespace plugslam;
using namespace plugslam::runtime::render;

namespace {

// The map: 10 m x 5 m at 5 cm, origin (-1, -2), free everywhere but a 10 cm wall at x = 3.
constexpr double kRes = 0.05, kOx = -1, kOy = -2, kWallX = 3.0;
constexpr int kW = 200, kH = 100;
const Rgb kEstimateColour{31, 119, 180};

using plugslam::testing::TempDir;  // a fresh folder per test, removed after

// Around a 2 m x 1.5 m rectangle, 5 cm per pose, 0.1 s apart.
std::vector<Eigen::Vector2d> rectangle() {
  std::vector<Eigen::Vector2d> corners{{0, 0}, {2, 0}, {2, 1.5}, {0, 1.5}, {0, 0}}, out;
  for (size_t c = 0; c + 1 < corners.size(); ++c) {
    const Eigen::Vector2d d = corners[c + 1] - corners[c];
    const int n = static_cast<int>(std::lround(d.norm() / 0.05));
    for (int i = 0; i < n; ++i) out.push_back(corners[c] + d * (double(i) / n));
  }
  out.push_back(corners.back());
  return out;
}

Trajectory toTrajectory(const std::vector<Eigen::Vector2d>& pts, const Eigen::Isometry3d& world) {
  Trajectory t;
  for (size_t i = 0; i < pts.size(); ++i) {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() << pts[i].x(), pts[i].y(), 0;
    t.push_back(0.1 * i, world * p);
  }
  return t;
}

void writeRun(const fs::path& dir, const Trajectory& est, const Trajectory& ref) {
  writeTumTrajectory(est, (dir / "trajectory.tum").string());
  writeTumTrajectory(ref, (dir / "reference.tum").string());
  std::ofstream pgm(dir / "map.pgm", std::ios::binary);
  pgm << "P5\n# render test\n" << kW << " " << kH << "\n255\n";
  for (int row = 0; row < kH; ++row)
    for (int col = 0; col < kW; ++col) {
      const double x = kOx + (col + 0.5) * kRes;
      pgm.put(static_cast<char>(x > kWallX && x < kWallX + 0.1 ? 0 : 254));
    }
  pgm.close();
  std::ofstream(dir / "map.yaml") << "image: map.pgm\nresolution: " << kRes << "\norigin: [" << kOx
                                  << ", " << kOy << ", 0.0]\nnegate: 0\n";
  // Four local maps at the corners; odometry 0-1-2-3, and one loop closure 2-0 (the diagonal).
  std::ofstream(dir / "graph.g2o")
      << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 2 0 1.57\nVERTEX_SE2 2 2 1.5 3.14\n"
         "VERTEX_SE2 3 0 1.5 -1.57\nFIX 0\n"
         "EDGE_SE2 0 1 2 0 1.57 1 0 0 1 0 1\nEDGE_SE2 1 2 1.5 0 1.57 1 0 0 1 0 1\n"
         "EDGE_SE2 2 3 2 0 1.57 1 0 0 1 0 1\nEDGE_SE2 2 0 -2 -1.5 -3.14 1 0 0 1 0 1\n";
}

bool near(Rgb a, Rgb b, int tol) {
  return std::abs(a.r - b.r) <= tol && std::abs(a.g - b.g) <= tol && std::abs(a.b - b.b) <= tol;
}

// Which of estimate, reference, free map and loop colour c is nearest to (0, 1, 2, 3).
int closest(Rgb c) {
  const Rgb palette[] = {kEstimateColour, {255, 127, 14}, {254, 254, 254}, {214, 39, 40}};
  int best = 0;
  double best_d = 1e9;
  for (int i = 0; i < 4; ++i) {
    const double d = std::hypot(c.r - palette[i].r, c.g - palette[i].g, c.b - palette[i].b);
    if (d < best_d) best_d = d, best = i;
  }
  return best;
}

Rgb pixelAt(const RgbImage& c, const Eigen::Vector2d& px) {
  return c.at(static_cast<int>(std::floor(px.x())), static_cast<int>(std::floor(px.y())));
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The vertices of every path an SVG strokes in colour c. Cairo writes no classes, so a series is
// found by its colour; it also merges collinear steps, so a path holds the corners only.
std::vector<std::vector<Eigen::Vector2d>> svgPaths(const std::string& svg, Rgb c) {
  std::vector<std::vector<Eigen::Vector2d>> out;
  const std::regex element("<path [^>]*>");
  // Cairo 1.16 writes style="stroke:rgb(...)", later versions stroke="rgb(...)".
  const std::regex colour("stroke(?::\\s*|=\")rgb\\(([0-9.]+)%,\\s*([0-9.]+)%,\\s*([0-9.]+)%\\)");
  const std::regex data(" d=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), element);
       it != std::sregex_iterator(); ++it) {
    const std::string e = it->str();
    std::smatch m, d;
    if (!std::regex_search(e, m, colour) || !std::regex_search(e, d, data)) continue;
    if (std::abs(std::stod(m[1]) - c.r / 2.55) > 0.5 ||
        std::abs(std::stod(m[2]) - c.g / 2.55) > 0.5 ||
        std::abs(std::stod(m[3]) - c.b / 2.55) > 0.5)
      continue;
    std::istringstream in(d[1].str());
    std::vector<Eigen::Vector2d> pts;
    std::string op;
    double x, y;
    while (in >> op) {
      if (op == "Z" || op == "z") continue;
      EXPECT_TRUE(op == "M" || op == "L") << "a stroked series is lines only: " << op;
      if (!(in >> x >> y)) break;
      pts.emplace_back(x, y);
    }
    out.push_back(std::move(pts));
  }
  return out;
}

// The longest of those paths: a trajectory rather than its legend's sample.
std::vector<Eigen::Vector2d> longestPath(const std::string& svg, Rgb c) {
  std::vector<Eigen::Vector2d> best;
  for (auto& p : svgPaths(svg, c))
    if (p.size() > best.size()) best = std::move(p);
  return best;
}

// Distance from q to the polyline through pts.
double toPolyline(const Eigen::Vector2d& q, const std::vector<Eigen::Vector2d>& pts) {
  double best = pts.empty() ? 1e9 : (q - pts[0]).norm();
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const Eigen::Vector2d d = pts[i + 1] - pts[i];
    const double t =
        d.squaredNorm() > 0 ? std::clamp((q - pts[i]).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (q - (pts[i] + t * d)).norm());
  }
  return best;
}

// An empty figure of that size in pixels, with its title.
Figure figure(int width, int height, const std::string& title) {
  Figure f;
  f.width = width;
  f.height = height;
  f.title = title;
  return f;
}

class Render : public ::testing::Test {
 protected:
  TempDir tmp;
  std::vector<Eigen::Vector2d> path = rectangle();
  Eigen::Isometry3d ref_world = [] {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.rotate(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
    t.translation() << 5, -3, 0;
    return t;
  }();
  void SetUp() override {
    writeRun(tmp.path(), toTrajectory(path, Eigen::Isometry3d::Identity()),
             toTrajectory(path, ref_world));
  }
};

TEST_F(Render, MapPictureDrawsTrajectoryLoopsAndMapWhereTheyAre) {
  const auto written = renderRun(tmp.path().string(), tmp.path().string());
  ASSERT_EQ(written.size(), 4u);
  const RunData run = loadRun(tmp.path().string());
  EXPECT_EQ(run.dimension, 2);
  EXPECT_EQ(run.nodes.size(), 4u);
  ASSERT_EQ(run.loop_ends.size(), 2u) << "one loop closure (2-0); odometry edges are not loops";
  const Figure fig = mapFigure(run);
  ASSERT_EQ(fig.panels.size(), 1u);
  const Panel& p = fig.panels[0];
  // Equal axes: one metre is as many pixels across as up.
  EXPECT_NEAR(p.width / (p.x_max - p.x_min), p.height / (p.y_max - p.y_min), 1e-6);

  const RgbImage png = readPng((tmp.path() / "render_map.png").string());
  ASSERT_EQ(png.width, fig.width);
  ASSERT_EQ(png.height, fig.height);
  // The wall of the map is black at its place in metres.
  EXPECT_TRUE(near(pixelAt(png, p.toPixel({kWallX + 0.05, 0.5})), {0, 0, 0}, 10));
  // Free map cells stay the map's grey away from everything drawn.
  EXPECT_TRUE(near(pixelAt(png, p.toPixel({1.5, 0.3})), {254, 254, 254}, 2));
  EXPECT_TRUE(near(pixelAt(png, p.toPixel({6.0, -1.0})), {254, 254, 254}, 2));
  // The estimate: its colour under every pose away from the node and start markers.
  int checked = 0;
  for (const auto& q : path) {
    bool by_marker = false;
    for (const auto& n : run.nodes) by_marker |= (q - n).norm() < 0.25;
    if (by_marker) continue;
    const Rgb c = pixelAt(png, p.toPixel(q));
    EXPECT_EQ(closest(c), 0) << "pose (" << q.transpose() << ") -> " << int(c.r) << "," << int(c.g)
                             << "," << int(c.b);
    ++checked;
  }
  EXPECT_GT(checked, 80);
  // The loop closure from (2, 1.5) to (0, 0): reddish at its middle, over the free grey.
  const Rgb mid = pixelAt(png, p.toPixel({1.0, 0.75}));
  EXPECT_GT(mid.r, mid.g + 40) << int(mid.r) << "," << int(mid.g) << "," << int(mid.b);

  // The SVG draws the same: the estimate at the PNG's pixel positions, and the reference (given
  // in another frame, rotated by 0.5 rad and moved by (5, -3)) aligned onto it. Every vertex
  // Cairo wrote lies on the path, and the path passes through every pose.
  const std::string svg = slurp(tmp.path() / "render_map.svg");
  std::vector<Eigen::Vector2d> want;
  for (const auto& q : path) want.push_back(p.toPixel(q));
  const auto est = longestPath(svg, kEstimateColour), ref = longestPath(svg, {255, 127, 14});
  ASSERT_GE(est.size(), 5u) << "the rectangle's corners at least";
  ASSERT_GE(ref.size(), 5u);
  // Cairo keeps coordinates in 1/256 px; the alignment adds its round-off.
  for (const auto& v : est) EXPECT_LT(toPolyline(v, want), 0.01) << v.transpose();
  for (const auto& v : ref) EXPECT_LT(toPolyline(v, want), 0.02) << v.transpose();
  for (size_t i = 0; i < want.size(); ++i) {
    EXPECT_LT(toPolyline(want[i], est), 0.01) << i;
    EXPECT_LT(toPolyline(want[i], ref), 0.02) << i;
  }
  EXPECT_NE(svg.find("<image style=\"image-rendering:pixelated\""), std::string::npos)
      << "the map is embedded, its cells unblurred";
  ASSERT_EQ(p.notes.size(), 1u);
  EXPECT_EQ(p.notes[0], "ATE RMSE 0.000 m (se2 alignment)");
}

TEST_F(Render, AMergedRunDrawsEachSessionInItsColourAndTheLinks) {
  // What `plugslam merge` adds to an output folder: a trajectory per session and merge.json.
  const std::vector<Eigen::Vector2d> first(path.begin(), path.begin() + path.size() / 2),
      second(path.begin() + path.size() / 2, path.end());
  writeTumTrajectory(toTrajectory(first, Eigen::Isometry3d::Identity()),
                     (tmp.path() / "trajectory_1.tum").string());
  std::vector<StampedPose> later;
  for (const auto& p : toTrajectory(second, Eigen::Isometry3d::Identity()))
    later.push_back({p.t + 1000, p.pose});
  writeTumTrajectory(Trajectory(later), (tmp.path() / "trajectory_2.tum").string());
  std::ofstream(tmp.path() / "merge.json")
      << R"({"sessions": [{"session": "/x/robot1/session", "joined": true,
                           "trajectory": "/y/trajectory_1.tum"},
                          {"session": "/x/robot2", "joined": true,
                           "trajectory": "/y/trajectory_2.tum"},
                          {"session": "/x/elsewhere", "joined": false, "trajectory": null}],
            "link_list": [{"from": 0, "to": 3}]})";
  const RunData run = loadRun(tmp.path().string());
  ASSERT_EQ(run.sessions.size(), 2u) << "the session that did not join is not drawn";
  EXPECT_EQ(run.sessions[0].first, "robot1");
  EXPECT_EQ(run.sessions[1].first, "robot2");
  ASSERT_EQ(run.link_ends.size(), 2u);
  EXPECT_EQ(run.link_ends[0], run.nodes[0]);
  EXPECT_EQ(run.link_ends[1], run.nodes[3]);
  renderRun(tmp.path().string(), tmp.path().string());
  const Figure fig = mapFigure(run);
  const Panel& p = fig.panels[0];
  const std::string svg = slurp(tmp.path() / "render_map.svg");
  // Each session's path in its colour, through its own poses only.
  const auto one = longestPath(svg, kEstimateColour), two = longestPath(svg, {44, 160, 44});
  ASSERT_GE(one.size(), 2u);
  ASSERT_GE(two.size(), 2u);
  for (const auto& q : first) EXPECT_LT(toPolyline(p.toPixel(q), one), 0.01);
  for (const auto& q : second) EXPECT_LT(toPolyline(p.toPixel(q), two), 0.01);
  // The link, in the reference's orange, from map 0 to map 3.
  const auto links = svgPaths(svg, {255, 127, 14});
  bool found = false;
  for (const auto& l : links)
    found |= l.size() >= 2 && (l.front() - p.toPixel(run.nodes[0])).norm() < 0.05 &&
             (l.back() - p.toPixel(run.nodes[3])).norm() < 0.05;
  EXPECT_TRUE(found) << "no link drawn from map 0 to map 3";
}

TEST_F(Render, ErrorPlotsShowTheErrorOfEachPose) {
  // Without alignment, a reference 0.1 m off in y for the first half and 0.3 m for the second
  // half gives ATE 0.1 then 0.3 at every pose: the curve must sit at those heights.
  Trajectory ref;
  const Trajectory est = toTrajectory(path, Eigen::Isometry3d::Identity());
  const double half = est[est.size() / 2].t;
  for (const auto& p : est) {
    Eigen::Isometry3d q = p.pose;
    q.translation().y() += p.t < half ? 0.1 : 0.3;
    ref.push_back(p.t, q);
  }
  writeTumTrajectory(ref, (tmp.path() / "reference.tum").string());
  RenderOptions o;
  o.alignment = Alignment::None;
  const auto written = renderRun(tmp.path().string(), tmp.path().string(), o);
  ASSERT_EQ(written.size(), 4u);
  const Figure fig = errorFigure(loadRun(tmp.path().string(), o), o);
  ASSERT_EQ(fig.panels.size(), 4u) << "ATE/time, ATE/distance, RPE translation, RPE rotation";
  const RgbImage png = readPng((tmp.path() / "render_errors.png").string());
  ASSERT_EQ(png.width, fig.width);
  ASSERT_EQ(png.height, fig.height);
  const Panel& p = fig.panels[0];
  const double per_px = (p.y_max - p.y_min) / p.height;
  for (double t : {0.1 * half, 0.4 * half, 1.3 * half, 1.8 * half}) {
    const int col = static_cast<int>(p.toPixel({t, 0}).x());
    double sum = 0;
    int n = 0;
    for (int row = p.y; row < p.y + p.height; ++row)
      if (near(png.at(col, row), kEstimateColour, 60)) sum += row + 0.5, ++n;
    ASSERT_GT(n, 0) << "no curve in column " << col;
    const double value = p.toData({col + 0.5, sum / n}).y();
    // The 1.5 px line is centred on the value: its colour's middle row is within 2 px of it.
    EXPECT_NEAR(value, t < half ? 0.1 : 0.3, 2 * per_px) << "t = " << t;
  }
  // The SVG: a curve in each panel; the first one's corners sit at 0.1 and 0.3 m and span the
  // time of the run.
  const std::string svg = slurp(tmp.path() / "render_errors.svg");
  const auto curves = svgPaths(svg, kEstimateColour);
  for (const Panel& q : fig.panels) {
    size_t inside = 0;
    for (const auto& c : curves) {
      bool in = c.size() > 1;
      for (const auto& v : c)
        in &= v.x() >= q.x - 0.01 && v.x() <= q.x + q.width + 0.01 && v.y() >= q.y - 0.01 &&
              v.y() <= q.y + q.height + 0.01;
      inside += in;
    }
    EXPECT_EQ(inside, 1u) << q.title;
  }
  std::vector<Eigen::Vector2d> ate_time;
  for (const auto& c : curves)
    if (!c.empty() && c[0].y() >= p.y && c[0].y() <= p.y + p.height) ate_time = c;
  ASSERT_GE(ate_time.size(), 2u);
  for (const auto& v : ate_time) {
    const double value = p.toData(v).y();
    EXPECT_TRUE(std::abs(value - 0.1) < 0.01 * per_px || std::abs(value - 0.3) < 0.01 * per_px)
        << value;
  }
  EXPECT_NEAR(p.toData(ate_time.front()).x(), 0.0, 1e-2);
  EXPECT_NEAR(p.toData(ate_time.back()).x(), est[est.size() - 1].t - est[0].t, 1e-2);
}

TEST_F(Render, WithoutReferenceOnlyTheMapIsDrawn) {
  fs::remove(tmp.path() / "reference.tum");
  const auto written = renderRun(tmp.path().string(), (tmp.path() / "pictures").string());
  ASSERT_EQ(written.size(), 2u);
  EXPECT_TRUE(fs::exists(tmp.path() / "pictures" / "render_map.png"));
  EXPECT_FALSE(fs::exists(tmp.path() / "pictures" / "render_errors.png"));
  EXPECT_THROW(errorFigure(loadRun(tmp.path().string())), InputError);
}

TEST_F(Render, BadInputNamesTheFile) {
  fs::remove(tmp.path() / "trajectory.tum");
  try {
    loadRun(tmp.path().string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.tum"), std::string::npos) << e.what();
  }
  writeTumTrajectory(toTrajectory(path, Eigen::Isometry3d::Identity()),
                     (tmp.path() / "trajectory.tum").string());
  std::ofstream(tmp.path() / "map.pgm") << "P6\n1 1\n255\n";
  try {
    loadRun(tmp.path().string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("map.pgm"), std::string::npos) << e.what();
  }
}

TEST(RenderFigure, TicksAreRoundAndCoverTheRange) {
  // The step is the first of 1, 2, 5 x 10^k at least (range / target): at most `target` ticks.
  const auto t = niceTicks(-0.3, 2.7, 5);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_DOUBLE_EQ(t.front(), 0.0);
  EXPECT_DOUBLE_EQ(t[1] - t[0], 1.0);
  const auto u = niceTicks(0.0, 1.0, 5);
  ASSERT_EQ(u.size(), 6u);
  EXPECT_NEAR(u[1] - u[0], 0.2, 1e-12);
  EXPECT_NEAR(u.back(), 1.0, 1e-12);
  EXPECT_EQ(tickLabel(0.5, 0.5), "0.5");
  EXPECT_EQ(tickLabel(20, 10), "20");
}

// Text in a real font, antialiased: dark strokes and the greys at their edges, where the title
// goes; PNG files read back pixel for pixel.
TEST(RenderFigure, TextIsDrawnAndPngRoundTrips) {
  TempDir tmp;
  Figure f = figure(120, 40, "0.5 m");
  const RgbImage img = rasterize(f);
  ASSERT_EQ(img.width, 120);
  ASSERT_EQ(img.height, 40);
  int dark = 0, edge = 0, outside = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 120; ++x) {
      const int v = img.at(x, y).r;
      const bool in_title = y >= 6 && y < 6 + textLineHeight() && x > 30 && x < 90;
      if (!in_title) outside += v != 255;
      if (in_title && v < 100) ++dark;
      if (in_title && v >= 100 && v < 230) ++edge;
    }
  EXPECT_GT(dark, 20) << "the glyphs' strokes";
  EXPECT_GT(edge, 10) << "antialiased edges";
  EXPECT_EQ(outside, 0) << "nothing but the title is drawn";
  writePng((tmp.path() / "c.png").string(), img);
  const RgbImage back = readPng((tmp.path() / "c.png").string());
  ASSERT_EQ(back.width, 120);
  ASSERT_EQ(back.height, 40);
  EXPECT_EQ(back.samples, img.samples);
  EXPECT_THROW(readPng((tmp.path() / "missing.png").string()), InputError);
  std::ofstream(tmp.path() / "not.png") << "GIF89a";
  EXPECT_THROW(readPng((tmp.path() / "not.png").string()), InputError);
}

// One figure, three formats chosen by the file's extension.
TEST(RenderFigure, WritesPngSvgAndPdfByExtension) {
  TempDir tmp;
  Figure f = figure(200, 150, "formats");
  Panel p;
  p.x = 40, p.y = 30, p.width = 140, p.height = 90;
  p.series.push_back({"line", "line", Series::Kind::Line, {200, 0, 0}, 2, 1, {{0, 0}, {1, 1}}});
  f.panels.push_back(p);
  for (const char* ext : {"png", "svg", "pdf", "PDF"})
    writeFigure(f, (tmp.path() / (std::string("f.") + ext)).string());
  EXPECT_EQ(readPng((tmp.path() / "f.png").string()).width, 200);
  const std::string svg = slurp(tmp.path() / "f.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("width=\"200"), std::string::npos) << "one SVG unit per pixel";
  EXPECT_EQ(svgPaths(svg, {200, 0, 0}).size(), 2u) << "the series and its legend sample";
  const std::string pdf = slurp(tmp.path() / "f.pdf");
  EXPECT_EQ(pdf.rfind("%PDF-", 0), 0u);
  EXPECT_NE(pdf.find("%%EOF"), std::string::npos);
  EXPECT_NE(pdf.find("FontFile"), std::string::npos) << "the font is embedded";
  EXPECT_THROW(writeFigure(f, (tmp.path() / "f.gif").string()), InputError);
  EXPECT_FALSE(fs::exists(tmp.path() / "f.gif"));
}

// `plugslam ARGS` as a user runs it: its exit code, and stdout and stderr in `out`.
int plugslamCli(const std::string& args, std::string& out) {
  plugslam::testing::CommandResult r =
      plugslam::testing::runCommand(plugslam::testing::buildDir() + "/bin/plugslam " + args);
  out = std::move(r.out);
  return r.code;
}

// The CLI as a user runs it: exit codes and the files it says it wrote.
TEST_F(Render, CommandLine) {
  auto run = [](const std::string& args, std::string& out) {
    return plugslamCli("render " + args, out);
  };
  std::string out;
  ASSERT_EQ(run(tmp.path().string() + " --width 640", out), 0) << out;
  EXPECT_NE(out.find("render_map.png"), std::string::npos) << out;
  EXPECT_NE(out.find("render_errors.svg"), std::string::npos) << out;
  EXPECT_LE(readPng((tmp.path() / "render_map.png").string()).width, 640);
  ASSERT_EQ(run(tmp.path().string() + " --format pdf -o " + (tmp.path() / "pdf").string(), out), 0)
      << out;
  EXPECT_TRUE(fs::exists(tmp.path() / "pdf" / "render_map.pdf"));
  EXPECT_TRUE(fs::exists(tmp.path() / "pdf" / "render_errors.pdf"));
  EXPECT_FALSE(fs::exists(tmp.path() / "pdf" / "render_map.png"));
  EXPECT_NE(run(tmp.path().string() + " --format gif", out), 0) << out;
  EXPECT_EQ(run((tmp.path() / "nowhere").string(), out), 2) << out;
  EXPECT_NE(out.find("is not a folder"), std::string::npos) << out;
}

// `plugslam view HOST:PORT` prints the page of a remote host; bad addresses exit 2.
TEST(ViewCommand, PrintsThePageAddress) {
  auto view = [](const std::string& args, std::string& out) {
    return plugslamCli("view " + args, out);
  };
  std::string out;
  EXPECT_EQ(view("robot.local:9000", out), 0);
  EXPECT_EQ(out, "http://robot.local:9000/\n");
  EXPECT_EQ(view(":8800", out), 0);
  EXPECT_EQ(out, "http://127.0.0.1:8800/\n");
  EXPECT_EQ(view("", out), 0);
  EXPECT_EQ(out, "http://127.0.0.1:8765/\n");
  EXPECT_EQ(view("[::1]:8765", out), 0);
  EXPECT_EQ(out, "http://[::1]:8765/\n");
  EXPECT_EQ(view("host:99999", out), 2) << out;
  EXPECT_EQ(view("host:abc", out), 2) << out;
}

}  // namespace
