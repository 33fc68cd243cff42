#pragma once
// A figure as data: panels with axes in data units, series drawn over them, an optional grey
// raster (an occupancy map) under them. One drawing over Cairo makes every format (PNG, SVG,
// PDF), so all pictures of a figure show the same thing at the same positions.
#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "render/image.h"

namespace plugslam::runtime::render {

/// A grey image placed in data coordinates: column 0 at x0, the last row at y0 (image rows run
/// top-down, as in PGM and ROS map_server), `resolution` data units per pixel.
struct GreyRaster {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;  ///< row-major, row 0 at the top
  double x0 = 0, y0 = 0;        ///< data coordinates of the bottom-left corner
  double resolution = 1;        ///< data units per pixel
};

/// One drawn thing: a polyline, separate segments (pairs of points) or dots.
struct Series {
  enum class Kind { Line, Segments, Points };
  std::string label;      ///< legend text (empty: not in the legend)
  std::string css_class;  ///< what the series is ("estimate", "loops"), for code that finds it
  Kind kind = Kind::Line;
  Rgb color;
  double width = 2;                     ///< line width or dot diameter [px]
  double alpha = 1;                     ///< opacity
  std::vector<Eigen::Vector2d> points;  ///< data coordinates
};

/// A plot area on the figure with its own data range.
struct Panel {
  int x = 0, y = 0, width = 0, height = 0;            ///< plot area on the figure [px]
  double x_min = 0, x_max = 1, y_min = 0, y_max = 1;  ///< data range shown
  std::string title, x_label, y_label;
  std::vector<std::string> notes;  ///< lines of text in the top-right corner
  bool axes = true;                ///< ticks, labels and frame
  std::optional<GreyRaster> background;
  std::vector<Series> series;

  /// Figure pixel of a data point (y grows upwards in data, downwards in pixels).
  Eigen::Vector2d toPixel(const Eigen::Vector2d& p) const;
  /// Data point at a figure pixel.
  Eigen::Vector2d toData(const Eigen::Vector2d& px) const;
};

/// A whole picture.
struct Figure {
  int width = 800, height = 600;
  std::string title;
  std::vector<Panel> panels;
};

/// Round tick positions covering [lo, hi], about `target` of them (steps 1, 2, 5 x 10^k).
std::vector<double> niceTicks(double lo, double hi, int target);
/// A tick label: as few decimals as the step needs.
std::string tickLabel(double value, double step);

/// Height of one line of figure text [px]: what a layout leaves for a note or a label.
int textLineHeight();

/// Draws the figure into an RGB raster of figure.width x figure.height pixels.
RgbImage rasterize(const Figure& figure);
/// The figure as a standalone SVG document, one user unit per pixel (text as glyph outlines).
std::string toSvg(const Figure& figure);
/// The figure as a one-page PDF, one point per pixel (fonts embedded).
std::string toPdf(const Figure& figure);
/// Writes the figure atomically in the format its extension names: .png, .svg or .pdf. Throws
/// InputError for another extension or when the file cannot be written.
void writeFigure(const Figure& figure, const std::string& path);

}  // namespace plugslam::runtime::render
