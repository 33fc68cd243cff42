#include "render/figure.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"

namespace plugslam::runtime::render {

namespace {

const Rgb kInk{40, 40, 40};
const Rgb kGrid{225, 225, 225};
const Rgb kFrame{120, 120, 120};
const Rgb kWhite{255, 255, 255};
constexpr double kFontPx = 13;
constexpr int kLine = 14;           // the layouts below were made for 14 px lines
constexpr double kBaseline = 11.5;  // from a line's top: capitals sit in the middle of the line

enum class Align { Left, Center, Right };

using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

void check(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS)
    throw Error(std::string("render: ") + what + ": " + cairo_status_to_string(status));
}

void setColor(cairo_t* cr, Rgb c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0, std::clamp(alpha, 0.0, 1.0));
}

bool finite(const Eigen::Vector2d& p) { return std::isfinite(p.x()) && std::isfinite(p.y()); }

// The middle of the pixel at v: a 1 px line there covers one pixel column instead of blurring
// over two.
double crisp(double v) { return std::floor(v) + 0.5; }

void hairline(cairo_t* cr, double x0, double y0, double x1, double y1, Rgb c) {
  setColor(cr, c);
  cairo_set_line_width(cr, 1);
  cairo_new_path(cr);
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1, y1);
  cairo_stroke(cr);
}

void fillRect(cairo_t* cr, double x0, double y0, double x1, double y1, Rgb c) {
  setColor(cr, c);
  cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
  cairo_fill(cr);
}

// Cairo puts a context into an error state for good on invalid UTF-8 (a folder name in another
// encoding): such bytes become '?'.
std::string validUtf8(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    const size_t n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    bool ok = n > 0 && i + n <= s.size();
    for (size_t k = 1; ok && k < n; ++k) ok = (static_cast<unsigned char>(s[i + k]) >> 6) == 2;
    if (ok && c >= 0x20) {
      out.append(s, i, n);
      i += n;
    } else {
      out += '?';
      ++i;
    }
  }
  return out;
}

double textWidth(cairo_t* cr, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, validUtf8(s).c_str(), &e);
  return e.x_advance;
}

// Text with the top of its line at `top`.
void text(cairo_t* cr, double x, double top, const std::string& s, Rgb c,
          Align align = Align::Left) {
  const std::string t = validUtf8(s);
  const double w = textWidth(cr, t);
  if (align == Align::Center) x -= w / 2;
  if (align == Align::Right) x -= w;
  setColor(cr, c);
  cairo_new_path(cr);
  cairo_move_to(cr, x, top + kBaseline);
  cairo_show_text(cr, t.c_str());
}

// The raster with each k x k block of cells reduced to its darkest, so walls one cell thin
// survive when a pixel covers many cells.
Surface greySurface(const GreyRaster& r, int k) {
  const int w = (r.width + k - 1) / k, h = (r.height + k - 1) / k;
  Surface s(cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h), cairo_surface_destroy);
  check(cairo_surface_status(s.get()), "map image");
  cairo_surface_flush(s.get());
  unsigned char* data = cairo_image_surface_get_data(s.get());
  const int stride = cairo_image_surface_get_stride(s.get());
  for (int by = 0; by < h; ++by) {
    auto* row = reinterpret_cast<uint32_t*>(data + static_cast<size_t>(by) * stride);
    for (int bx = 0; bx < w; ++bx) {
      uint32_t v = 255;
      for (int y = by * k; y < std::min(r.height, (by + 1) * k); ++y)
        for (int x = bx * k; x < std::min(r.width, (bx + 1) * k); ++x)
          v = std::min<uint32_t>(v, r.pixels[static_cast<size_t>(y) * r.width + x]);
      row[bx] = 0xff000000u | v << 16 | v << 8 | v;
    }
  }
  cairo_surface_mark_dirty(s.get());
  return s;
}

void drawRaster(cairo_t* cr, const Panel& p, const GreyRaster& r) {
  if (r.width <= 0 || r.height <= 0 || !(r.resolution > 0) ||
      r.pixels.size() < static_cast<size_t>(r.width) * r.height)
    return;
  const Eigen::Vector2d tl = p.toPixel({r.x0, r.y0 + r.height * r.resolution});
  const Eigen::Vector2d br = p.toPixel({r.x0 + r.width * r.resolution, r.y0});
  const double sx = (br.x() - tl.x()) / r.width, sy = (br.y() - tl.y()) / r.height;
  if (!finite(tl) || !finite(br) || !(sx > 0) || !(sy > 0)) return;
  // Blocks at least a pixel across: each holds a pixel centre, so nearest-neighbour sampling
  // skips none of them.
  const double cells_per_px = 1.0 / std::min(sx, sy);
  const int k = cells_per_px > 1 ? static_cast<int>(std::min<double>(std::ceil(cells_per_px - 1e-9),
                                                                     std::max(r.width, r.height)))
                                 : 1;
  const Surface img = greySurface(r, k);
  cairo_save(cr);
  cairo_rectangle(cr, p.x, p.y, p.width, p.height);
  cairo_clip(cr);
  cairo_rectangle(cr, tl.x(), tl.y(), br.x() - tl.x(), br.y() - tl.y());
  cairo_clip(cr);
  cairo_translate(cr, tl.x(), tl.y());
  cairo_scale(cr, sx * k, sy * k);
  cairo_set_source_surface(cr, img.get(), 0, 0);
  // Cells are cells: a map blurred between them would show walls that are not there.
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
}

void drawSeries(cairo_t* cr, const Panel& p, const Series& s) {
  setColor(cr, s.color, s.alpha);
  cairo_set_line_width(cr, s.width);
  const auto& pts = s.points;
  if (s.kind == Series::Kind::Line) {
    // One path per figure: joints are not painted twice under a translucent colour. NaN points
    // are gaps.
    cairo_new_path(cr);
    bool open = false;
    for (const auto& q : pts) {
      if (!finite(q)) {
        open = false;
        continue;
      }
      const Eigen::Vector2d a = p.toPixel(q);
      if (open) {
        cairo_line_to(cr, a.x(), a.y());
      } else {
        cairo_move_to(cr, a.x(), a.y());
      }
      open = true;
    }
    cairo_stroke(cr);
    return;
  }
  // Segments and dots are painted one by one, so where many overlap (thousands of loop
  // closures) the colour deepens with their density.
  if (s.kind == Series::Kind::Points) {
    for (const auto& q : pts) {
      if (!finite(q)) continue;
      const Eigen::Vector2d a = p.toPixel(q);
      cairo_new_path(cr);
      cairo_arc(cr, a.x(), a.y(), s.width / 2, 0, 2 * M_PI);
      cairo_fill(cr);
    }
    return;
  }
  for (size_t i = 0; i + 1 < pts.size(); i += 2) {
    if (!finite(pts[i]) || !finite(pts[i + 1])) continue;
    const Eigen::Vector2d a = p.toPixel(pts[i]), b = p.toPixel(pts[i + 1]);
    cairo_new_path(cr);
    cairo_move_to(cr, a.x(), a.y());
    cairo_line_to(cr, b.x(), b.y());
    cairo_stroke(cr);
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

// The title in one line, or two (split after "name:") when it is wider than the figure.
std::vector<std::string> titleLines(cairo_t* cr, const Figure& f) {
  const int room = f.width - 16;
  if (f.title.empty()) return {};
  if (textWidth(cr, f.title) <= room) return {f.title};
  std::vector<std::string> lines;
  const size_t colon = f.title.find(": ");
  if (colon == std::string::npos) {
    lines = {f.title};
  } else {
    lines = {f.title.substr(0, colon + 1), f.title.substr(colon + 2)};
  }
  for (auto& l : lines) {
    while (l.size() > 4 && textWidth(cr, l) > room) l.pop_back();
  }
  return lines;
}

void drawPanel(cairo_t* cr, const Panel& p) {
  const Ticks t = ticksOf(p);
  if (p.background) drawRaster(cr, p, *p.background);
  if (p.axes && !p.background) {
    for (double v : t.x) {
      const double px = crisp(p.toPixel({v, p.y_min}).x());
      hairline(cr, px, p.y, px, p.y + p.height, kGrid);
    }
    for (double v : t.y) {
      const double py = crisp(p.toPixel({p.x_min, v}).y());
      hairline(cr, p.x, py, p.x + p.width, py, kGrid);
    }
  }
  cairo_save(cr);
  cairo_rectangle(cr, p.x, p.y, p.width, p.height);
  cairo_clip(cr);
  for (const Series& s : p.series) drawSeries(cr, p, s);
  cairo_restore(cr);
  if (p.axes) {
    // The frame just outside the plot area: it hides no data at the edges.
    setColor(cr, kFrame);
    cairo_set_line_width(cr, 1);
    cairo_new_path(cr);
    cairo_rectangle(cr, p.x - 0.5, p.y - 0.5, p.width + 1, p.height + 1);
    cairo_stroke(cr);
    for (double v : t.x) {
      const double px = crisp(p.toPixel({v, p.y_min}).x());
      hairline(cr, px, p.y + p.height, px, p.y + p.height + 5, kFrame);
      text(cr, px, p.y + p.height + 9, tickLabel(v, stepOf(t.x)), kInk, Align::Center);
    }
    for (double v : t.y) {
      const double py = crisp(p.toPixel({p.x_min, v}).y());
      hairline(cr, p.x - 5, py, p.x, py, kFrame);
      text(cr, p.x - 9, py - kLine / 2.0, tickLabel(v, stepOf(t.y)), kInk, Align::Right);
    }
    if (!p.x_label.empty())
      text(cr, p.x + p.width / 2.0, p.y + p.height + 30, p.x_label, kInk, Align::Center);
    if (!p.y_label.empty()) text(cr, p.x, p.y - kLine - 6, p.y_label, kInk);
  }
  if (!p.title.empty())
    text(cr, p.x + p.width / 2.0, p.y - kLine - 6, p.title, kInk, Align::Center);
  // Legend rows top-left inside the panel: a sample of the line, then the label.
  int y = p.y + 8;
  for (const Series& s : p.series) {
    if (s.label.empty()) continue;
    fillRect(cr, p.x + 4, y - 3, p.x + 44 + textWidth(cr, s.label), y + kLine + 3, kWhite);
    setColor(cr, s.color);
    cairo_set_line_width(cr, std::max(2.0, s.width));
    cairo_new_path(cr);
    cairo_move_to(cr, p.x + 10, y + kLine / 2.0);
    cairo_line_to(cr, p.x + 32, y + kLine / 2.0);
    cairo_stroke(cr);
    text(cr, p.x + 38, y, s.label, kInk);
    y += kLine + 6;
  }
  // Notes top-right, on white so a curve under them does not hide them.
  y = p.y + 8;
  for (const std::string& n : p.notes) {
    const double w = textWidth(cr, n);
    fillRect(cr, p.x + p.width - w - 12, y - 3, p.x + p.width - 4, y + kLine + 3, kWhite);
    text(cr, p.x + p.width - 8, y, n, kInk, Align::Right);
    y += kLine + 6;
  }
}

// The one drawing of a figure, whatever surface it goes onto.
void draw(cairo_surface_t* surface, const Figure& f) {
  Context owner(cairo_create(surface), cairo_destroy);
  cairo_t* cr = owner.get();
  // The toy API's family goes through fontconfig: DejaVu Sans on Debian (fonts-dejavu-core).
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, kFontPx);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  setColor(cr, kWhite);
  cairo_paint(cr);
  double ty = 6;
  for (const std::string& line : titleLines(cr, f)) {
    text(cr, f.width / 2.0, ty, line, kInk, Align::Center);
    ty += kLine + 4;
  }
  for (const Panel& p : f.panels) drawPanel(cr, p);
  check(cairo_status(cr), "drawing the figure");
}

void checkSize(const Figure& f) {
  // Cairo's image surfaces stop at 32767 px a side.
  if (f.width <= 0 || f.height <= 0 || f.width > 32767 || f.height > 32767)
    throw InputError(
        fmt::format("figure size {}x{}: each side must be 1 to 32767 px", f.width, f.height));
}

cairo_status_t appendBytes(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// Draws onto a document surface (owned from here on); the document is complete in its stream
// once the surface is finished, before this returns.
void drawDocument(cairo_surface_t* raw, const char* format, const Figure& f) {
  Surface surface(raw, cairo_surface_destroy);
  check(cairo_surface_status(surface.get()), format);
  draw(surface.get(), f);
  cairo_surface_finish(surface.get());
  check(cairo_surface_status(surface.get()), format);
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

int textLineHeight() { return kLine; }

RgbImage rasterize(const Figure& f) {
  checkSize(f);
  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, f.width, f.height),
                  cairo_surface_destroy);
  check(cairo_surface_status(surface.get()), "image");
  draw(surface.get(), f);
  cairo_surface_flush(surface.get());
  RgbImage image;
  image.width = f.width;
  image.height = f.height;
  image.samples.resize(static_cast<size_t>(f.width) * f.height * 3);
  const unsigned char* data = cairo_image_surface_get_data(surface.get());
  const int stride = cairo_image_surface_get_stride(surface.get());
  for (int y = 0; y < f.height; ++y) {
    const auto* row = reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride);
    for (int x = 0; x < f.width; ++x) {
      uint8_t* px = &image.samples[(static_cast<size_t>(y) * f.width + x) * 3];
      px[0] = static_cast<uint8_t>(row[x] >> 16);
      px[1] = static_cast<uint8_t>(row[x] >> 8);
      px[2] = static_cast<uint8_t>(row[x]);
    }
  }
  return image;
}

std::string toSvg(const Figure& f) {
  checkSize(f);
  std::string out;
  cairo_surface_t* s = cairo_svg_surface_create_for_stream(appendBytes, &out, f.width, f.height);
  // Pixels, not points: the SVG opens at the PNG's size.
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS)
    cairo_svg_surface_set_document_unit(s, CAIRO_SVG_UNIT_PX);
  drawDocument(s, "SVG", f);
  // Cairo 1.16 writes no filter for an SVG image: viewers would blur the map's cells, which
  // the PNG and PDF show sharp.
  for (size_t at = out.find("<image "); at != std::string::npos; at = out.find("<image ", at + 1)) {
    const size_t end = out.find('>', at);
    if (out.substr(at, end - at).find("style=") != std::string::npos) continue;
    out.insert(at + 7, "style=\"image-rendering:pixelated\" ");
  }
  return out;
}

std::string toPdf(const Figure& f) {
  checkSize(f);
  std::string out;
  cairo_surface_t* s = cairo_pdf_surface_create_for_stream(appendBytes, &out, f.width, f.height);
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
    cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE, validUtf8(f.title).c_str());
    cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, "plugslam");
  }
  drawDocument(s, "PDF", f);
  return out;
}

void writeFigure(const Figure& f, const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".png") {
    writePng(path, rasterize(f));
  } else if (ext == ".svg") {
    writeFileAtomically(path, toSvg(f));
  } else if (ext == ".pdf") {
    writeFileAtomically(path, toPdf(f));
  } else {
    throw InputError("'" + path + "': a picture is .png, .svg or .pdf");
  }
}

}  // namespace plugslam::runtime::render
