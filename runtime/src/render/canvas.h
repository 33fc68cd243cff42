#pragma once
// An RGB raster for `plugslam render`: anti-aliased lines and discs, a built-in 5x7 bitmap font
// (no font package needed on the host), and PNG files through libpng.
#include <cstdint>
#include <string>
#include <vector>

namespace plugslam::runtime::render {

/// An 8-bit RGB colour.
struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb& o) const { return r == o.r && g == o.g && b == o.b; }
};

/// Horizontal placement of a text relative to its anchor.
enum class Align { Left, Center, Right };

/// A width x height RGB image, row-major from the top-left corner.
class Canvas {
 public:
  Canvas(int width, int height, Rgb background);

  int width() const { return width_; }
  int height() const { return height_; }
  /// The pixel at (x, y); (x, y) must be inside.
  Rgb at(int x, int y) const;
  /// Sets a pixel; outside the canvas it is ignored.
  void set(int x, int y, Rgb c);
  /// Mixes c into a pixel with weight alpha in [0, 1]; outside the canvas it is ignored.
  void blend(int x, int y, Rgb c, double alpha);
  /// A segment between pixel-space points (pixel centres at integer + 0.5), `width` pixels wide,
  /// edges anti-aliased.
  void line(double x0, double y0, double x1, double y1, Rgb c, double width, double alpha = 1.0);
  /// A filled disc of radius r around (cx, cy).
  void disc(double cx, double cy, double r, Rgb c, double alpha = 1.0);
  /// A filled axis-aligned rectangle [x0, x1) x [y0, y1).
  void fill(int x0, int y0, int x1, int y1, Rgb c);
  /// Restricts drawing to [x0, x1) x [y0, y1) until unclip().
  void clip(int x0, int y0, int x1, int y1);
  /// Drawing reaches the whole canvas again.
  void unclip() { clip(0, 0, width_, height_); }
  /// Text in the built-in font, `scale` pixels per font dot; (x, y) is the top of the glyphs.
  /// Lower case is drawn as upper case; characters the font lacks are drawn as '?'.
  void text(int x, int y, const std::string& s, Rgb c, int scale = 2, Align align = Align::Left);
  /// Width in pixels of text drawn at this scale.
  static int textWidth(const std::string& s, int scale = 2);
  /// Height in pixels of one line of text at this scale.
  static int textHeight(int scale = 2) { return 7 * scale; }

  /// The samples, 3 per pixel, row-major.
  const std::vector<uint8_t>& samples() const { return rgb_; }

 private:
  int width_, height_;
  int cx0_ = 0, cy0_ = 0, cx1_, cy1_;  // clip rectangle
  std::vector<uint8_t> rgb_;
};

/// Encodes the canvas as an 8-bit sRGB PNG (the SDK's encoder).
std::string encodePng(const Canvas& canvas);
/// Writes the canvas as a PNG atomically; throws InputError on failure.
void writePng(const std::string& path, const Canvas& canvas);
/// Reads any PNG as RGB (grey expanded, alpha composed on black, 16 bit reduced); throws
/// InputError if the file cannot be read or is not a valid PNG.
Canvas readPng(const std::string& path);

}  // namespace plugslam::runtime::render
