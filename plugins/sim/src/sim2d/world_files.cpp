// World loaders: the segment-list text format and PGM occupancy images.
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

#include "plugslam/errors.h"
#include "sim2d/world.h"

namespace plugslam {
namespace sim {
namespace sim2d {
namespace {

// Parses a whole token as a finite double; false on trailing garbage or overflow.
bool parseDouble(const std::string& token, double* value) {
  errno = 0;
  char* end = nullptr;
  *value = std::strtod(token.c_str(), &end);
  return end != token.c_str() && *end == '\0' && errno == 0 && std::isfinite(*value);
}

// Reads the PGM header and pixel tokens while tracking 1-based line numbers for errors.
class PgmReader {
 public:
  PgmReader(std::string path, std::string bytes)
      : path_(std::move(path)), data_(std::move(bytes)) {}

  // Skips whitespace and '#' comments, then returns the next whitespace-delimited token.
  std::string token(const char* what) {
    while (pos_ < data_.size()) {
      const char c = data_[pos_];
      if (c == '#') {
        while (pos_ < data_.size() && data_[pos_] != '\n') ++pos_;
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        if (c == '\n') ++line_;
        ++pos_;
      } else {
        break;
      }
    }
    if (pos_ >= data_.size()) fail(std::string("unexpected end of file, expected ") + what);
    const size_t start = pos_;
    while (pos_ < data_.size() && !std::isspace(static_cast<unsigned char>(data_[pos_])) &&
           data_[pos_] != '#') {
      ++pos_;
    }
    return data_.substr(start, pos_ - start);
  }

  // Parses the next token as an integer in [lo, hi].
  long integer(const char* what, long lo, long hi) {
    const std::string t = token(what);
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(t.c_str(), &end, 10);
    if (end == t.c_str() || *end != '\0' || errno != 0 || v < lo || v > hi) {
      fail(std::string("expected ") + what + " (an integer in [" + std::to_string(lo) + ", " +
           std::to_string(hi) + "]), got '" + t + "'");
    }
    return v;
  }

  // After maxval of a P5 file: exactly one whitespace byte, then raw pixels.
  size_t binaryStart() {
    if (pos_ >= data_.size() || !std::isspace(static_cast<unsigned char>(data_[pos_]))) {
      fail("expected one whitespace byte before the binary pixel data");
    }
    if (data_[pos_] == '\n') ++line_;
    return ++pos_;
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw ParseError(path_, line_, message);
  }

  const std::string& data() const { return data_; }
  int line() const { return line_; }

 private:
  std::string path_;
  std::string data_;
  size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace

World World::loadSegments(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("sim2d world: cannot open segment file '" + path + "'");
  std::vector<Segment> segments;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::vector<std::string> tokens{std::istream_iterator<std::string>(fields),
                                    std::istream_iterator<std::string>()};
    if (tokens.empty()) continue;
    if (tokens.size() != 4) {
      throw ParseError(
          path, number,
          "expected four numbers 'x1 y1 x2 y2', got " + std::to_string(tokens.size()) + " fields");
    }
    double v[4];
    for (int k = 0; k < 4; ++k) {
      if (!parseDouble(tokens[k], &v[k])) {
        throw ParseError(path, number,
                         "expected a finite number for field " + std::to_string(k + 1) +
                             " of 'x1 y1 x2 y2', got '" + tokens[k] + "'");
      }
    }
    Segment s{Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3])};
    if (s.a == s.b) throw ParseError(path, number, "expected two distinct end points, got a point");
    segments.push_back(s);
  }
  if (in.bad()) throw InputError("sim2d world: error reading '" + path + "'");
  if (segments.empty()) throw ParseError(path, number, "expected at least one segment line");
  return World(std::move(segments));
}

World World::loadPgm(const std::string& path, double resolution, const Eigen::Vector2d& origin,
                     double occupied_threshold) {
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    throw InputError("sim2d world: PGM resolution must be a positive number of metres per pixel");
  }
  if (!origin.allFinite()) throw InputError("sim2d world: PGM origin must be finite");
  if (!(occupied_threshold >= 0.0 && occupied_threshold < 1.0)) {
    throw InputError("sim2d world: PGM occupied_threshold must be in [0, 1)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("sim2d world: cannot open PGM file '" + path + "'");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  PgmReader reader(path, std::move(bytes));

  const std::string magic = reader.token("the magic number P2 or P5");
  if (magic != "P2" && magic != "P5")
    reader.fail("expected magic number P2 or P5, got '" + magic + "'");
  const long width = reader.integer("the image width", 1, 1 << 15);
  const long height = reader.integer("the image height", 1, 1 << 15);
  const long maxval = reader.integer("the maximum grey value", 1, 65535);

  std::vector<uint16_t> pixels(static_cast<size_t>(width) * height);
  if (magic == "P2") {
    for (size_t i = 0; i < pixels.size(); ++i) {
      pixels[i] = static_cast<uint16_t>(reader.integer("a grey value", 0, maxval));
    }
  } else {
    const size_t start = reader.binaryStart();
    const size_t bpp = maxval < 256 ? 1 : 2;
    const std::string& d = reader.data();
    if (d.size() < start + pixels.size() * bpp) {
      reader.fail("expected " + std::to_string(pixels.size() * bpp) +
                  " bytes of pixel data, file has " + std::to_string(d.size() - start));
    }
    for (size_t i = 0; i < pixels.size(); ++i) {
      const auto* p = reinterpret_cast<const unsigned char*>(d.data() + start + i * bpp);
      pixels[i] = bpp == 1 ? p[0] : static_cast<uint16_t>((p[0] << 8) | p[1]);
      if (pixels[i] > maxval) reader.fail("grey value above maxval " + std::to_string(maxval));
    }
  }

  auto occupied = [&](long c, long r) {
    if (c < 0 || r < 0 || c >= width || r >= height) return false;
    const double p = static_cast<double>(maxval - pixels[r * width + c]) / maxval;
    return p > occupied_threshold;
  };
  auto corner = [&](long c, long image_row_edge) {
    // image_row_edge counts pixel edges from the image top (0 = top border).
    return Eigen::Vector2d(origin.x() + resolution * c,
                           origin.y() + resolution * (height - image_row_edge));
  };

  std::vector<Segment> segments;
  // Horizontal sides: top side of (c,r) at edge r, bottom side at edge r+1; runs along c merge.
  for (long r = 0; r < height; ++r) {
    for (int side = 0; side < 2; ++side) {
      const long nr = side == 0 ? r - 1 : r + 1;
      long c = 0;
      while (c < width) {
        if (occupied(c, r) && !occupied(c, nr)) {
          const long c0 = c;
          while (c < width && occupied(c, r) && !occupied(c, nr)) ++c;
          const long edge = side == 0 ? r : r + 1;
          segments.push_back({corner(c0, edge), corner(c, edge)});
        } else {
          ++c;
        }
      }
    }
  }
  // Vertical sides: left side of (c,r) at x edge c, right side at c+1; runs along r merge.
  for (long c = 0; c < width; ++c) {
    for (int side = 0; side < 2; ++side) {
      const long nc = side == 0 ? c - 1 : c + 1;
      long r = 0;
      while (r < height) {
        if (occupied(c, r) && !occupied(nc, r)) {
          const long r0 = r;
          while (r < height && occupied(c, r) && !occupied(nc, r)) ++r;
          const long xedge = side == 0 ? c : c + 1;
          segments.push_back({corner(xedge, r0), corner(xedge, r)});
        } else {
          ++r;
        }
      }
    }
  }
  if (segments.empty()) {
    throw InputError("sim2d world: PGM '" + path + "' has no occupied pixel (threshold " +
                     std::to_string(occupied_threshold) + ")");
  }
  return World(std::move(segments));
}

}  // namespace sim2d
}  // namespace sim
}  // namespace plugslam
