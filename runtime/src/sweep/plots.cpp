// The report's pictures: a metric against one swept parameter, one line per dataset (per
// dataset and config when the sweep has several configs), drawn with the render module's
// figures, as `plugslam render` draws a run.
#include <fmt/format.h>

#include <algorithm>
#include <boost/filesystem.hpp>
#include <cmath>
#include <map>
#include <set>

#include "render/figure.h"
#include "sweep/metrics.h"
#include "sweep/report.h"

namespace plugslam::runtime::sweep {

namespace fs = boost::filesystem;

namespace {

const std::vector<render::Rgb> kPalette{{31, 119, 180}, {255, 127, 14}, {44, 160, 44},
                                        {214, 39, 40},  {148, 103, 189}, {140, 86, 75},
                                        {227, 119, 194}, {127, 127, 127}, {188, 189, 34},
                                        {23, 190, 207}};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string fileWord(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_' ? c : '_';
  return out;
}

}  // namespace

std::vector<std::string> drawPlots(const SweepTable& t, const std::string& dir) {
  std::vector<std::string> files;
  const Plan& p = t.plan;
  const bool by_config = p.config_labels.size() > 1;
  for (size_t k = 0; k < p.swept_keys.size(); ++k) {
    const std::string& key = p.swept_keys[k];
    // The key's values in plan order; numbers are placed by value, anything else by position.
    std::vector<std::string> values;
    for (const auto& r : t.rows) {
      const std::string& v = r.first->params.at(k).second;
      if (std::find(values.begin(), values.end(), v) == values.end()) values.push_back(v);
    }
    if (values.size() < 2) continue;
    bool numeric = true;
    std::map<std::string, double> x_of;
    for (size_t i = 0; i < values.size(); ++i) {
      try {
        size_t used = 0;
        const double x = std::stod(values[i], &used);
        if (used != values[i].size() || !std::isfinite(x)) numeric = false;
        x_of[values[i]] = x;
      } catch (const std::exception&) {
        numeric = false;
      }
    }
    if (!numeric)
      for (size_t i = 0; i < values.size(); ++i) x_of[values[i]] = static_cast<double>(i);
    for (const auto& metric : p.metrics) {
      // line -> x -> the grid points' medians there (over the other parameters' values)
      std::map<std::string, std::map<double, std::vector<double>>> lines;
      std::vector<std::string> order;
      for (const auto& r : t.rows) {
        auto it = r.metrics.find(metric);
        if (it == r.metrics.end()) continue;
        const std::string line = by_config ? r.first->dataset + " / " + r.first->config_label
                                           : r.first->dataset;
        if (!lines.count(line)) order.push_back(line);
        lines[line][x_of[r.first->params.at(k).second]].push_back(it->second.median);
      }
      if (lines.empty()) continue;
      render::Figure f;
      f.width = 900;
      f.height = 560;
      const MetricInfo* info = findMetric(metric, t.plan.custom_metrics);
      const std::string y_label = info && !info->unit.empty() ? metric + " [" + info->unit + "]" : metric;
      f.title = fmt::format("{} against {}", metric, key);
      render::Panel panel;
      panel.x = 90;
      panel.y = 70;
      panel.width = f.width - 130;
      panel.height = f.height - 150;
      panel.x_label = key;
      panel.y_label = y_label;
      double y0 = 1e300, y1 = -1e300;
      for (size_t li = 0; li < order.size(); ++li) {
        render::Series s;
        s.label = order[li];
        s.css_class = "metric-line";
        s.color = kPalette[li % kPalette.size()];
        s.width = 2.5;
        for (const auto& [x, ys] : lines[order[li]]) {
          const double y = median(ys);
          s.points.emplace_back(x, y);
          y0 = std::min(y0, y);
          y1 = std::max(y1, y);
        }
        render::Series dots = s;
        dots.label.clear();
        dots.css_class = "metric-points";
        dots.kind = render::Series::Kind::Points;
        dots.width = 7;
        panel.series.push_back(std::move(s));
        panel.series.push_back(std::move(dots));
      }
      const double x0 = x_of[values.front()], x1 = x_of[values.back()];
      const double xlo = std::min(x0, x1), xhi = std::max(x0, x1);
      double xmin = xlo, xmax = xhi;
      for (const auto& [v, x] : x_of) {
        xmin = std::min(xmin, x);
        xmax = std::max(xmax, x);
      }
      const double xpad = (xmax - xmin) * 0.05 + (xmax == xmin ? 1 : 0);
      panel.x_min = xmin - xpad;
      panel.x_max = xmax + xpad;
      const double span = y1 > y0 ? y1 - y0 : std::max(std::fabs(y1), 1e-9);
      // Room above the lines for the legend in the top-left corner.
      panel.y_min = y0 - 0.08 * span;
      panel.y_max = y1 + (0.12 + 0.09 * static_cast<double>(order.size())) * span;
      if (!numeric) {
        std::string legend;
        for (size_t i = 0; i < values.size(); ++i) legend += fmt::format("{}{}={}", i ? ", " : "", i, values[i]);
        panel.notes.push_back("x: " + legend);
      }
      f.panels.push_back(std::move(panel));
      fs::create_directories(dir);
      // The PNG for the report page, the SVG for a paper or slides (one drawing, both files).
      const std::string stem = (fs::path(dir) / (fileWord(metric) + "-vs-" + fileWord(key))).string();
      render::writeFigure(f, stem + ".png");
      render::writeFigure(f, stem + ".svg");
      files.push_back(stem + ".png");
    }
  }
  return files;
}

}  // namespace plugslam::runtime::sweep
