#include "render/figure.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace plugslam::runtime::render {

namespace {

const Rgb kInk{40, 40, 40};
const Rgb kGrid{225, 225, 225};
const Rgb kFrame{120, 120, 120};
constexpr int kFont = 2;  // raster text: 2 px per font dot, 14 px tall lines
constexpr int kSvgFontPx = 14;

std::string hex(Rgb c) { return fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b); }

std::string escapeXml(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* kTable = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 2]);
    out += kTable[(v >> 18) & 63];
    out += kTable[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kTable[(v >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kTable[v & 63] : '=';
  }
  return out;
}

bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// The darkest raster cell under each panel pixel, so thin walls survive a downscale.
void drawRaster(Canvas& c, const Panel& p, const GreyRaster& r) {
  for (int py = p.y; py < p.y + p.height; ++py) {
    for (int px = p.x; px < p.x + p.width; ++px) {
      const Eigen::Vector2d a = p.toData({px, py + 1.0}), b = p.toData({px + 1.0, py});
      const int c0 = static_cast<int>(std::floor((a.x() - r.x0) / r.resolution));
      const int c1 = static_cast<int>(std::ceil((b.x() - r.x0) / r.resolution)) - 1;
      const int r0 = r.height - static_cast<int>(std::ceil((b.y() - r.y0) / r.resolution));
      const int r1 = r.height - 1 - static_cast<int>(std::floor((a.y() - r.y0) / r.resolution));
      if (c1 < 0 || r1 < 0 || c0 >= r.width || r0 >= r.height) continue;
      int v = 255;
      for (int row = std::max(0, r0); row <= std::min(r.height - 1, std::max(r0, r1)); ++row)
        for (int col = std::max(0, c0); col <= std::min(r.width - 1, std::max(c0, c1)); ++col)
          v = std::min<int>(v, r.pixels[static_cast<size_t>(row) * r.width + col]);
      const uint8_t g = static_cast<uint8_t>(v);
      c.set(px, py, {g, g, g});
    }
  }
}

struct Ticks {
  std::vector<double> x, y;
};

Ticks ticksOf(const Panel& p) {
  return {niceTicks(p.x_min, p.x_max, std::max(2, p.width / 110)),
          niceTicks(p.y_min, p.y_max, std::max(3, p.height / 45))};
}

double stepOf(const std::vector<double>& t) { return t.size() > 1 ? t[1] - t[0] : 1.0; }

// Legend rows: a line sample and the label, top-left inside the panel.
struct LegendRow {
  const Series* series;
  int y;
};
std::vector<LegendRow> legendOf(const Panel& p) {
  std::vector<LegendRow> rows;
  int y = p.y + 8;
  for (const Series& s : p.series)
    if (!s.label.empty()) {
      rows.push_back({&s, y});
      y += Canvas::textHeight(kFont) + 6;
    }
  return rows;
}

// The title in one line, or two (split after "name:") when it is wider than the figure.
std::vector<std::string> titleLines(const Figure& f) {
  const int room = f.width - 16;
  if (f.title.empty()) return {};
  if (Canvas::textWidth(f.title, kFont) <= room) return {f.title};
  std::vector<std::string> lines;
  const size_t colon = f.title.find(": ");
  if (colon == std::string::npos) {
    lines = {f.title};
  } else {
    lines = {f.title.substr(0, colon + 1), f.title.substr(colon + 2)};
  }
  for (auto& l : lines) {
    while (l.size() > 4 && Canvas::textWidth(l, kFont) > room) l.pop_back();
  }
  return lines;
}

}  // namespace

Eigen::Vector2d Panel::toPixel(const Eigen::Vector2d& p) const {
  return {x + (p.x() - x_min) / (x_max - x_min) * width,
          y + (y_max - p.y()) / (y_max - y_min) * height};
}

Eigen::Vector2d Panel::toData(const Eigen::Vector2d& px) const {
  return {x_min + (px.x() - x) / width * (x_max - x_min),
          y_max - (px.y() - y) / height * (y_max - y_min)};
}

std::vector<double> niceTicks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  const double raw = (hi - lo) / std::max(1, target);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  double step = mag;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * mag >= raw) {
      step = m * mag;
      break;
    }
  for (double t = std::ceil(lo / step) * step; t <= hi + step * 1e-9; t += step)
    ticks.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  return ticks;
}

std::string tickLabel(double value, double step) {
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  return fmt::format("{:.{}f}", value, std::clamp(decimals, 0, 6));
}

Canvas rasterize(const Figure& f) {
  Canvas c(f.width, f.height, {255, 255, 255});
  int ty = 6;
  for (const std::string& line : titleLines(f)) {
    c.text(f.width / 2, ty, line, kInk, kFont, Align::Center);
    ty += Canvas::textHeight(kFont) + 4;
  }
  for (const Panel& p : f.panels) {
    const Ticks t = ticksOf(p);
    if (p.background) drawRaster(c, p, *p.background);
    if (p.axes && !p.background) {
      for (double v : t.x) {
        const double px = p.toPixel({v, p.y_min}).x();
        c.line(px, p.y, px, p.y + p.height, kGrid, 1);
      }
      for (double v : t.y) {
        const double py = p.toPixel({p.x_min, v}).y();
        c.line(p.x, py, p.x + p.width, py, kGrid, 1);
      }
    }
    c.clip(p.x, p.y, p.x + p.width, p.y + p.height);
    for (const Series& s : p.series) {
      auto px = [&](const Eigen::Vector2d& q) { return p.toPixel(q); };
      const auto& pts = s.points;
      if (s.kind == Series::Kind::Points) {
        for (const auto& q : pts)
          if (finite(q)) {
            const Eigen::Vector2d a = px(q);
            c.disc(a.x(), a.y(), s.width / 2, s.color, s.alpha);
          }
        continue;
      }
      const size_t step = s.kind == Series::Kind::Segments ? 2 : 1;
      for (size_t i = 0; i + 1 < pts.size(); i += step) {
        if (!finite(pts[i]) || !finite(pts[i + 1])) continue;
        const Eigen::Vector2d a = px(pts[i]), b = px(pts[i + 1]);
        c.line(a.x(), a.y(), b.x(), b.y(), s.color, s.width, s.alpha);
      }
    }
    c.unclip();
    if (p.axes) {
      c.line(p.x, p.y, p.x + p.width, p.y, kFrame, 1);
      c.line(p.x, p.y + p.height, p.x + p.width, p.y + p.height, kFrame, 1);
      c.line(p.x, p.y, p.x, p.y + p.height, kFrame, 1);
      c.line(p.x + p.width, p.y, p.x + p.width, p.y + p.height, kFrame, 1);
      for (double v : t.x) {
        const double px = p.toPixel({v, p.y_min}).x();
        c.line(px, p.y + p.height, px, p.y + p.height + 5, kFrame, 1);
        c.text(static_cast<int>(px), p.y + p.height + 9, tickLabel(v, stepOf(t.x)), kInk, kFont,
               Align::Center);
      }
      for (double v : t.y) {
        const double py = p.toPixel({p.x_min, v}).y();
        c.line(p.x - 5, py, p.x, py, kFrame, 1);
        c.text(p.x - 9, static_cast<int>(py) - Canvas::textHeight(kFont) / 2,
               tickLabel(v, stepOf(t.y)), kInk, kFont, Align::Right);
      }
      if (!p.x_label.empty())
        c.text(p.x + p.width / 2, p.y + p.height + 30, p.x_label, kInk, kFont, Align::Center);
      if (!p.y_label.empty())
        c.text(p.x, p.y - Canvas::textHeight(kFont) - 6, p.y_label, kInk, kFont, Align::Left);
    }
    if (!p.title.empty())
      c.text(p.x + p.width / 2, p.y - Canvas::textHeight(kFont) - 6, p.title, kInk, kFont,
             Align::Center);
    for (const LegendRow& row : legendOf(p)) {
      const int h = Canvas::textHeight(kFont);
      const int w = Canvas::textWidth(row.series->label, kFont);
      c.fill(p.x + 4, row.y - 3, p.x + 44 + w, row.y + h + 3, {255, 255, 255});
      c.line(p.x + 10, row.y + h / 2.0, p.x + 32, row.y + h / 2.0, row.series->color,
             std::max(2.0, row.series->width));
      c.text(p.x + 38, row.y, row.series->label, kInk, kFont);
    }
    int ny = p.y + 8;
    for (const std::string& n : p.notes) {
      const int w = Canvas::textWidth(n, kFont);
      c.fill(p.x + p.width - w - 12, ny - 3, p.x + p.width - 4, ny + Canvas::textHeight(kFont) + 3,
             {255, 255, 255});
      c.text(p.x + p.width - 8, ny, n, kInk, kFont, Align::Right);
      ny += Canvas::textHeight(kFont) + 6;
    }
  }
  return c;
}

std::string toSvg(const Figure& f) {
  std::string s = fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" "
      "viewBox=\"0 0 {0} {1}\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" "
      "font-size=\"{2}\">\n<rect width=\"{0}\" height=\"{1}\" fill=\"#ffffff\"/>\n",
      f.width, f.height, kSvgFontPx);
  int ty = 6 + kSvgFontPx;
  for (const std::string& line : titleLines(f)) {
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"{}\">{}</text>\n",
                     f.width / 2, ty, hex(kInk), escapeXml(line));
    ty += Canvas::textHeight(kFont) + 4;
  }
  int index = 0;
  for (const Panel& p : f.panels) {
    const Ticks t = ticksOf(p);
    const std::string clip = fmt::format("panel{}", index++);
    s += fmt::format(
        "<clipPath id=\"{}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>\n"
        "<g class=\"panel\">\n",
        clip, p.x, p.y, p.width, p.height);
    if (p.background) {
      const GreyRaster& r = *p.background;
      Canvas img(r.width, r.height, {});
      for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
          const uint8_t g = r.pixels[static_cast<size_t>(y) * r.width + x];
          img.set(x, y, {g, g, g});
        }
      const Eigen::Vector2d tl = p.toPixel({r.x0, r.y0 + r.height * r.resolution});
      const Eigen::Vector2d br = p.toPixel({r.x0 + r.width * r.resolution, r.y0});
      s += fmt::format(
          "<image class=\"map\" clip-path=\"url(#{})\" x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" "
          "height=\"{:.2f}\" preserveAspectRatio=\"none\" style=\"image-rendering:pixelated\" "
          "href=\"data:image/png;base64,{}\"/>\n",
          clip, tl.x(), tl.y(), br.x() - tl.x(), br.y() - tl.y(), base64(encodePng(img)));
    } else if (p.axes) {
      s += "<g stroke=\"" + hex(kGrid) + "\" stroke-width=\"1\">";
      for (double v : t.x) {
        const double px = p.toPixel({v, p.y_min}).x();
        s += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1}\" x2=\"{0:.2f}\" y2=\"{2}\"/>", px, p.y,
                         p.y + p.height);
      }
      for (double v : t.y) {
        const double py = p.toPixel({p.x_min, v}).y();
        s += fmt::format("<line x1=\"{1}\" y1=\"{0:.2f}\" x2=\"{2}\" y2=\"{0:.2f}\"/>", py, p.x,
                         p.x + p.width);
      }
      s += "</g>\n";
    }
    for (const Series& se : p.series) {
      const std::string style = fmt::format(
          "class=\"{}\" clip-path=\"url(#{})\" fill=\"none\" stroke=\"{}\" stroke-width=\"{:.2f}\" "
          "stroke-opacity=\"{:.2f}\" stroke-linejoin=\"round\" stroke-linecap=\"round\"",
          escapeXml(se.css_class), clip, hex(se.color), se.width, se.alpha);
      if (se.kind == Series::Kind::Line) {
        // A polyline per finite run: NaN points are gaps.
        std::string pts;
        auto flush = [&] {
          if (!pts.empty()) s += "<polyline " + style + " points=\"" + pts + "\"/>\n";
          pts.clear();
        };
        for (const auto& q : se.points) {
          if (!finite(q)) {
            flush();
            continue;
          }
          const Eigen::Vector2d a = p.toPixel(q);
          pts += fmt::format("{}{:.2f},{:.2f}", pts.empty() ? "" : " ", a.x(), a.y());
        }
        flush();
      } else {
        std::string d;
        const bool dots = se.kind == Series::Kind::Points;
        const size_t step = dots ? 1 : 2;
        for (size_t i = 0; i + (dots ? 0 : 1) < se.points.size(); i += step) {
          if (!finite(se.points[i]) || (!dots && !finite(se.points[i + 1]))) continue;
          const Eigen::Vector2d a = p.toPixel(se.points[i]);
          if (dots) {
            d += fmt::format("M{:.2f} {:.2f}h0", a.x(), a.y());
          } else {
            const Eigen::Vector2d b = p.toPixel(se.points[i + 1]);
            d += fmt::format("M{:.2f} {:.2f}L{:.2f} {:.2f}", a.x(), a.y(), b.x(), b.y());
          }
        }
        if (!d.empty()) s += "<path " + style + " d=\"" + d + "\"/>\n";
      }
    }
    if (p.axes) {
      s += fmt::format(
          "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"{}\"/>\n", p.x,
          p.y, p.width, p.height, hex(kFrame));
      for (double v : t.x) {
        const double px = p.toPixel({v, p.y_min}).x();
        s += fmt::format(
            "<line x1=\"{0:.2f}\" y1=\"{1}\" x2=\"{0:.2f}\" y2=\"{2}\" stroke=\"{3}\"/>"
            "<text x=\"{0:.2f}\" y=\"{4}\" text-anchor=\"middle\" fill=\"{5}\">{6}</text>\n",
            px, p.y + p.height, p.y + p.height + 5, hex(kFrame), p.y + p.height + 9 + kSvgFontPx,
            hex(kInk), tickLabel(v, stepOf(t.x)));
      }
      for (double v : t.y) {
        const double py = p.toPixel({p.x_min, v}).y();
        s += fmt::format(
            "<line x1=\"{1}\" y1=\"{0:.2f}\" x2=\"{2}\" y2=\"{0:.2f}\" stroke=\"{3}\"/>"
            "<text x=\"{4}\" y=\"{5:.2f}\" text-anchor=\"end\" fill=\"{6}\">{7}</text>\n",
            py, p.x - 5, p.x, hex(kFrame), p.x - 9, py + kSvgFontPx / 2.0 - 2, hex(kInk),
            tickLabel(v, stepOf(t.y)));
      }
      if (!p.x_label.empty())
        s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"{}\">{}</text>\n",
                         p.x + p.width / 2, p.y + p.height + 30 + kSvgFontPx, hex(kInk),
                         escapeXml(p.x_label));
      if (!p.y_label.empty())
        s += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"{}\">{}</text>\n", p.x, p.y - 8, hex(kInk),
                         escapeXml(p.y_label));
    }
    if (!p.title.empty())
      s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"{}\">{}</text>\n",
                       p.x + p.width / 2, p.y - 8, hex(kInk), escapeXml(p.title));
    for (const LegendRow& row : legendOf(p)) {
      const double mid = row.y + Canvas::textHeight(kFont) / 2.0;
      s += fmt::format(
          "<g class=\"legend\"><line x1=\"{0}\" y1=\"{1:.1f}\" x2=\"{2}\" y2=\"{1:.1f}\" "
          "stroke=\"{3}\" stroke-width=\"{4:.1f}\"/><text x=\"{5}\" y=\"{6:.1f}\" fill=\"{7}\" "
          "paint-order=\"stroke\" stroke=\"#ffffff\" stroke-width=\"4\">{8}</text></g>\n",
          p.x + 10, mid, p.x + 32, hex(row.series->color), std::max(2.0, row.series->width),
          p.x + 38, mid + kSvgFontPx / 2.0 - 2, hex(kInk), escapeXml(row.series->label));
    }
    int ny = p.y + 8;
    for (const std::string& n : p.notes) {
      s += fmt::format(
          "<text class=\"note\" x=\"{}\" y=\"{}\" text-anchor=\"end\" fill=\"{}\" "
          "paint-order=\"stroke\" stroke=\"#ffffff\" stroke-width=\"4\">{}</text>\n",
          p.x + p.width - 8, ny + kSvgFontPx - 2, hex(kInk), escapeXml(n));
      ny += Canvas::textHeight(kFont) + 6;
    }
    s += "</g>\n";
  }
  s += "</svg>\n";
  return s;
}

}  // namespace plugslam::runtime::render
