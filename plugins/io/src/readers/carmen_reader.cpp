#include "readers/carmen_reader.h"

#include <bzlib.h>
#include <sys/stat.h>
#include <zlib.h>

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "plugslam/errors.h"

namespace plugslam {
namespace io {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// from_chars rejects a leading '+', and reports under/overflow as an error where strtod
// saturates; the slow path only runs on such rare tokens.
bool parseDouble(const char* b, const char* e, double& out) {
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto r = std::from_chars(b, e, out);
  if (r.ec == std::errc() && r.ptr == e) return true;
  if (r.ec == std::errc::result_out_of_range && r.ptr == e) {
    std::string copy(b, e);
    out = std::strtod(copy.c_str(), nullptr);
    return true;
  }
  return false;
}

bool parseInt(const char* b, const char* e, long long& out) {
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto r = std::from_chars(b, e, out);
  return r.ec == std::errc() && r.ptr == e;
}

// CARMEN's own guesses for old-format scans (readlog.c: carmen_laser_guess_*).
double guessIncrement(std::size_t n) {
  if (n == 180 || n == 181) return kPi / 180.0;
  if (n == 360 || n == 361) return kPi / 360.0;
  if (n == 400 || n == 401) return kPi / 720.0;
  return n > 1 ? kPi / static_cast<double>(n - 1) : kPi;
}

}  // namespace

bool isRangeReturn(double range, double max_range) {
  return std::isfinite(range) && range > 0.0 && range < max_range;
}

// Plain, gzip or bzip2 bytes. zlib reads plain files transparently, so the magic only has to
// tell bzip2 apart (users keep logs as published, e.g. .clf.bz2).
class CarmenReader::Source {
 public:
  Source(const std::string& path, std::string& compression) : path_(path) {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
      throw InputError("'" + path + "' is a directory; expected a CARMEN log file");
    }
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError("cannot open CARMEN log '" + path + "': " + std::strerror(errno));
    unsigned char magic[3] = {0, 0, 0};
    std::size_t got = std::fread(magic, 1, 3, f);
    buffer_.resize(1 << 17);
    if (got == 3 && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h') {
      compression = "bzip2";
      std::rewind(f);
      file_ = f;
      openBz2(nullptr, 0);
      return;
    }
    std::fclose(f);
    compression = got >= 2 && magic[0] == 0x1f && magic[1] == 0x8b ? "gzip" : "";
    gz_ = gzopen(path.c_str(), "rb");
    if (!gz_) throw InputError("cannot open CARMEN log '" + path + "'");
    gzbuffer(gz_, 1 << 17);
  }
  // In-memory plain text: the whole buffer is one block, never refilled.
  explicit Source(std::string text) : buffer_(text.begin(), text.end()) {
    end_ = buffer_.size();
    eof_ = true;
  }
  ~Source() {
    if (gz_) gzclose(gz_);
    closeBz2();
    if (file_) std::fclose(file_);
  }

  // Appends the next line (without '\n') to line; false at end of data. Sets error on a
  // corrupt or truncated gzip stream (the data before the fault has been returned).
  bool getLine(std::string& line, bool& terminated, std::size_t max_bytes) {
    line.clear();
    terminated = false;
    for (;;) {
      if (pos_ == end_) {
        if (eof_) return !line.empty();
        fill();
        if (pos_ == end_) return !line.empty();
      }
      const char* b = buffer_.data() + pos_;
      const char* nl = static_cast<const char*>(std::memchr(b, '\n', end_ - pos_));
      std::size_t n = nl ? static_cast<std::size_t>(nl - b) : end_ - pos_;
      if (line.size() + n > max_bytes) {
        too_long_ = true;
        // Drop the rest of this line so the reader can skip it.
        pos_ += n;
        if (nl) {
          ++pos_;
          terminated = true;
          return true;
        }
        line.clear();
        continue;
      }
      line.append(b, n);
      pos_ += n;
      if (nl) {
        ++pos_;
        terminated = true;
        return true;
      }
    }
  }

  bool tooLong() {
    bool t = too_long_;
    too_long_ = false;
    return t;
  }
  const std::string& error() const { return error_; }

 private:
  void fill() {
    pos_ = end_ = 0;
    if (file_) {
      fillBz2();
      return;
    }
    int n = gzread(gz_, buffer_.data(), static_cast<unsigned>(buffer_.size()));
    if (n > 0) {
      end_ = static_cast<std::size_t>(n);
      return;
    }
    eof_ = true;
    int code = Z_OK;
    const char* msg = gzerror(gz_, &code);
    if (n < 0 || (code != Z_OK && code != Z_STREAM_END)) {
      error_ = std::string("gzip stream is corrupt or truncated (") + (msg ? msg : "?") + ")";
    }
  }

  void openBz2(void* unused, int unused_bytes) {
    int err = BZ_OK;
    bz_ = BZ2_bzReadOpen(&err, file_, 0, 0, unused, unused_bytes);
    if (err != BZ_OK) {
      closeBz2();
      throw InputError("cannot open CARMEN log '" + path_ + "' as bzip2 (libbz2 error " +
                       std::to_string(err) + ")");
    }
  }
  void closeBz2() {
    if (!bz_) return;
    int err = BZ_OK;
    BZ2_bzReadClose(&err, bz_);
    bz_ = nullptr;
  }
  void fillBz2() {
    while (bz_) {
      int err = BZ_OK;
      const int n = BZ2_bzRead(&err, bz_, buffer_.data(), static_cast<int>(buffer_.size()));
      if (err == BZ_OK) {
        end_ = static_cast<std::size_t>(n);
        return;
      }
      if (err != BZ_STREAM_END) {
        error_ = "bzip2 stream is corrupt or truncated (libbz2 error " + std::to_string(err) + ")";
        break;
      }
      // pbzip2 and `cat a.bz2 b.bz2` write several streams back to back: go on with the next.
      void* unused = nullptr;
      int unused_bytes = 0;
      BZ2_bzReadGetUnused(&err, bz_, &unused, &unused_bytes);
      std::vector<char> rest(static_cast<const char*>(unused),
                             static_cast<const char*>(unused) + unused_bytes);
      closeBz2();
      const int next = rest.empty() ? std::fgetc(file_) : EOF;
      if (next != EOF) rest.push_back(static_cast<char>(next));
      if (!rest.empty()) openBz2(rest.data(), static_cast<int>(rest.size()));
      if (n > 0) {
        end_ = static_cast<std::size_t>(n);
        return;
      }
    }
    eof_ = true;
  }

  std::string path_;
  std::FILE* file_{nullptr};
  BZFILE* bz_{nullptr};
  gzFile gz_{nullptr};
  std::vector<char> buffer_;
  std::size_t pos_{0}, end_{0};
  bool eof_{false};
  bool too_long_{false};
  std::string error_;
};

CarmenReader::CarmenReader(const std::string& path, CarmenReaderOptions options)
    : path_(path), options_(std::move(options)) {
  source_ = std::make_unique<Source>(path_, stats_.compression);
  stats_.compressed = !stats_.compression.empty();
  tokens_.reserve(512);
}

CarmenReader::CarmenReader(std::string name, std::string text, CarmenReaderOptions options)
    : path_(std::move(name)), options_(std::move(options)) {
  source_ = std::make_unique<Source>(std::move(text));
  tokens_.reserve(512);
}

std::unique_ptr<CarmenReader> CarmenReader::fromText(std::string name, std::string text,
                                                     CarmenReaderOptions options) {
  return std::unique_ptr<CarmenReader>(
      new CarmenReader(std::move(name), std::move(text), std::move(options)));
}

CarmenReader::~CarmenReader() = default;

void CarmenReader::fail(const std::string& message) const {
  std::string m = message;
  if (last_line_unterminated_) m += " (last line has no newline: file truncated?)";
  throw ParseError(path_, static_cast<int>(line_number_), m);
}

void CarmenReader::warn(const std::string& message) {
  ++stats_.warnings;
  if (options_.on_warning) options_.on_warning(ReaderWarning{path_, line_number_, message});
}

bool CarmenReader::readLine() {
  for (;;) {
    bool terminated = false;
    bool got = source_->getLine(line_, terminated, options_.max_line_bytes);
    // A line cut off by a broken compressed stream is the stream's fault, not the log's.
    if (got && !terminated && !source_->error().empty()) got = false;
    if (!got) {
      if (!source_->error().empty()) {
        stats_.truncated = true;
        std::string what = source_->error() + " after line " + std::to_string(line_number_);
        if (options_.policy == ErrorPolicy::kStrict) {
          throw ParseError(path_, static_cast<int>(line_number_), what);
        }
        warn(what + "; stopping there");
      }
      return false;
    }
    ++line_number_;
    ++stats_.lines;
    last_line_unterminated_ = !terminated;
    if (!source_->tooLong()) return true;
    std::string what = "line longer than " + std::to_string(options_.max_line_bytes) +
                       " bytes (binary data?); expected one text message per line";
    if (options_.policy == ErrorPolicy::kStrict) {
      throw ParseError(path_, static_cast<int>(line_number_), what);
    }
    ++stats_.malformed;
    warn(what + "; line skipped");
  }
}

std::string CarmenReader::rawToken(std::size_t index) const {
  return std::string(tokens_[index].first, tokens_[index].second);
}

std::string CarmenReader::token(std::size_t index) const {
  const auto& t = tokens_[index];
  std::string s(t.first, t.second);
  if (s.size() > 40) s = s.substr(0, 40) + "...";
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  return s;
}

void CarmenReader::expectTokens(std::size_t count, const char* layout) const {
  // The logger timestamp at the end is optional (some loggers omit it).
  if (tokens_.size() != count && tokens_.size() + 1 != count) {
    fail(token(0) + ": expected " + std::to_string(count) + " tokens (" + layout + "), found " +
         std::to_string(tokens_.size()));
  }
}

double CarmenReader::number(std::size_t index, const char* what) const {
  if (index >= tokens_.size()) {
    fail(token(0) + ": missing " + what + " (token " + std::to_string(index + 1) + ")");
  }
  double v = 0.0;
  if (!parseDouble(tokens_[index].first, tokens_[index].second, v)) {
    fail(token(0) + ": token " + std::to_string(index + 1) + " '" + token(index) +
         "' is not a number; expected " + what);
  }
  return v;
}

std::size_t CarmenReader::count(std::size_t index, const char* what) const {
  if (index >= tokens_.size()) {
    fail(token(0) + ": missing " + what + " (token " + std::to_string(index + 1) + ")");
  }
  long long v = 0;
  if (!parseInt(tokens_[index].first, tokens_[index].second, v) || v < 0) {
    fail(token(0) + ": token " + std::to_string(index + 1) + " '" + token(index) +
         "' is not a non-negative integer; expected " + what);
  }
  // Never trust a count beyond what the line can hold: it sizes an allocation.
  if (static_cast<unsigned long long>(v) > tokens_.size()) {
    fail(token(0) + ": " + what + " is " + std::to_string(v) + " but the line has only " +
         std::to_string(tokens_.size()) + " tokens");
  }
  return static_cast<std::size_t>(v);
}

int CarmenReader::smallInt(std::size_t index, const char* what) const {
  double v = number(index, what);
  if (!(std::fabs(v) < 1e6) || v != std::floor(v)) {
    fail(token(0) + ": token " + std::to_string(index + 1) + " '" + token(index) +
         "' is not a small integer; expected " + what);
  }
  return static_cast<int>(v);
}

std::string CarmenReader::sensorName(const std::string& kind, const char* fallback) const {
  auto it = options_.sensor_names.find(kind);
  return it != options_.sensor_names.end() ? it->second : std::string(fallback);
}

bool CarmenReader::next(CarmenRecord& record) {
  for (;;) {
    if (!readLine()) return false;
    bool produced = false;
    try {
      produced = parseLine(record);
    } catch (const ParseError& e) {
      if (options_.policy == ErrorPolicy::kStrict) throw;
      ++stats_.malformed;
      warn(e.message() + "; line skipped");
      continue;
    }
    if (!produced) continue;
    record.line = line_number_;
    if (last_line_unterminated_) {
      // The tokens added up, but the last number may still have been cut short.
      warn("last line has no newline (file truncated?); its record is kept");
    }
    if (record.kind == CarmenRecord::Kind::kLaser) {
      auto& l = record.laser;
      if (l.ranges.empty()) {
        ++stats_.empty_scans;
        warn(l.message + " with zero beams; scan skipped");
        continue;
      }
      l.time_backwards = false;
      if (l.has_timestamp) checkTime("laser:" + l.sensor, l.timestamp, l.time_backwards);
      ++stats_.lasers;
    } else if (record.kind == CarmenRecord::Kind::kOdometry) {
      auto& o = record.odometry;
      o.time_backwards = false;
      if (o.has_timestamp) checkTime("odom", o.timestamp, o.time_backwards);
      ++stats_.odometry;
    }
    return true;
  }
}

void CarmenReader::checkTime(const std::string& stream, double t, bool& backwards) {
  backwards = false;
  auto it = last_time_.find(stream);
  if (it == last_time_.end()) {
    last_time_.emplace(stream, t);
    return;
  }
  // Compare with the previous record, not the maximum: one outlier then flags one record.
  double previous = it->second;
  it->second = t;
  if (t >= previous) return;
  backwards = true;
  ++stats_.time_backwards;
  char buf[160];
  std::snprintf(buf, sizeof buf, "timestamp %.6f of %s goes backwards (previous was %.6f)", t,
                stream.c_str(), previous);
  ErrorPolicy p = options_.time_policy.value_or(options_.policy);
  if (p == ErrorPolicy::kStrict) {
    throw ParseError(path_, static_cast<int>(line_number_),
                     std::string(buf) + "; expected non-decreasing timestamps");
  }
  warn(std::string(buf) + "; record flagged");
}

bool CarmenReader::parseLine(CarmenRecord& record) {
  tokens_.clear();
  const char* p = line_.data();
  const char* e = p + line_.size();
  while (p != e) {
    while (p != e && isSpace(*p)) ++p;
    if (p == e) break;
    const char* b = p;
    while (p != e && !isSpace(*p)) ++p;
    tokens_.emplace_back(b, p);
  }
  if (tokens_.empty() || *tokens_[0].first == '#') {
    ++stats_.comments;
    return false;
  }
  std::string kind(tokens_[0].first, tokens_[0].second);
  // Binary garbage would otherwise fill the per-kind map with junk keys.
  bool printable = kind.size() <= 32;
  for (char c : kind) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) printable = false;
  }
  if (!printable) {
    fail("unrecognised line starting with '" + token(0) +
         "'; expected a CARMEN message name (FLASER, ODOM, PARAM, ...)");
  }
  ++stats_.kinds[kind];
  if (kind == "FLASER") {
    parseOldLaser(record, false);
  } else if (kind == "RLASER") {
    parseOldLaser(record, true);
  } else if (kind.rfind("ROBOTLASER", 0) == 0 && kind.size() == 11 && kind[10] >= '0' &&
             kind[10] <= '9') {
    parseRobotLaser(record, kind[10] - '0');
  } else if (kind.rfind("RAWLASER", 0) == 0 && kind.size() == 9 && kind[8] >= '0' &&
             kind[8] <= '9') {
    parseRawLaser(record, kind[8] - '0');
  } else if (kind == "ODOM") {
    parseOdometry(record);
  } else if (kind == "PARAM") {
    applyParam(record);
    return options_.emit_params;
  } else {
    ++stats_.unknown;
    return false;
  }
  return true;
}

void CarmenReader::parseOldLaser(CarmenRecord& record, bool rear) {
  const char* layout =
      "n ranges[n] x y theta odom_x odom_y odom_theta ipc_timestamp host logger_timestamp";
  std::size_t n = count(1, "the number of readings");
  expectTokens(n + 11, layout);
  record.kind = CarmenRecord::Kind::kLaser;
  CarmenLaser& l = record.laser;
  l.message = rear ? "RLASER" : "FLASER";
  l.sensor = sensorName(l.message, rear ? "rear" : "front");
  l.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i) l.ranges[i] = number(2 + i, "a range reading");
  l.remissions.clear();
  std::size_t k = 2 + n;
  l.has_pose = true;
  l.laser_pose = {number(k, "laser x"), number(k + 1, "laser y"), number(k + 2, "laser theta")};
  l.robot_pose = {number(k + 3, "odom x"), number(k + 4, "odom y"), number(k + 5, "odom theta")};
  l.timestamp = number(k + 6, "the ipc timestamp");
  l.host = rawToken(k + 7);
  l.logger_timestamp = tokens_.size() > k + 8 ? number(k + 8, "the logger timestamp") : 0.0;
  if (!std::isfinite(l.timestamp)) fail(l.message + ": expected a finite timestamp");
  for (double v : {l.laser_pose.x, l.laser_pose.y, l.laser_pose.theta, l.robot_pose.x,
                   l.robot_pose.y, l.robot_pose.theta}) {
    if (!std::isfinite(v)) fail(l.message + ": expected finite pose values");
  }
  l.has_timestamp = l.timestamp != 0.0;
  l.tv = l.rv = 0.0;
  l.laser_type = 0;
  l.accuracy = 0.0;
  l.remission_mode = 0;
  int s = rear ? 1 : 0;
  l.angle_increment = resolution_deg_[s] ? *resolution_deg_[s] * kDeg : guessIncrement(n);
  if (fov_deg_[s]) {
    l.fov = *fov_deg_[s] * kDeg;
    l.angle_min = -0.5 * l.fov;
  } else {
    l.fov = n > 1 ? static_cast<double>(n - 1) * l.angle_increment : 0.0;
    l.angle_min = -0.5 * kPi;
  }
  l.fov_from_log = fov_deg_[s].has_value() || resolution_deg_[s].has_value();
  l.max_range = options_.old_format_max_range;
  l.forward_offset = offset_[s];
}

std::size_t CarmenReader::parseLaserScan(CarmenLaser& l, std::size_t trailing, const char* layout) {
  l.laser_type = smallInt(1, "the laser type");
  l.angle_min = number(2, "the start angle");
  l.fov = number(3, "the field of view");
  l.angle_increment = number(4, "the angular resolution");
  l.max_range = number(5, "the maximum range");
  l.accuracy = number(6, "the accuracy");
  l.remission_mode = smallInt(7, "the remission mode");
  std::size_t n = count(8, "the number of readings");
  std::size_t m = count(9 + n, "the number of remissions");
  expectTokens(n + m + 10 + trailing, layout);
  l.ranges.resize(n);
  for (std::size_t i = 0; i < n; ++i) l.ranges[i] = number(9 + i, "a range reading");
  l.remissions.resize(m);
  for (std::size_t i = 0; i < m; ++i) l.remissions[i] = number(10 + n + i, "a remission value");
  return 10 + n + m;
}

void CarmenReader::parseRobotLaser(CarmenRecord& record, int index) {
  const char* layout =
      "laser_type start_angle fov resolution max_range accuracy remission_mode n ranges[n] m "
      "remissions[m] laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv "
      "forward_safety side_safety turn_axis ipc_timestamp host logger_timestamp";
  record.kind = CarmenRecord::Kind::kLaser;
  CarmenLaser& l = record.laser;
  l.message = "ROBOTLASER" + std::to_string(index);
  l.sensor = sensorName(l.message, index == 2 ? "rear" : index == 1 ? "front" : "robotlaser");
  if (index != 1 && index != 2 && !options_.sensor_names.count(l.message)) {
    l.sensor += std::to_string(index);
  }
  const std::size_t k = parseLaserScan(l, 14, layout);
  l.has_pose = true;
  l.laser_pose = {number(k, "laser x"), number(k + 1, "laser y"), number(k + 2, "laser theta")};
  l.robot_pose = {number(k + 3, "robot x"), number(k + 4, "robot y"), number(k + 5, "robot theta")};
  l.tv = number(k + 6, "tv");
  l.rv = number(k + 7, "rv");
  number(k + 8, "forward_safety_dist");
  number(k + 9, "side_safety_dist");
  number(k + 10, "turn_axis");
  l.timestamp = number(k + 11, "the ipc timestamp");
  l.host = rawToken(k + 12);
  l.logger_timestamp = tokens_.size() > k + 13 ? number(k + 13, "the logger timestamp") : 0.0;
  for (double v :
       {l.angle_min, l.fov, l.angle_increment, l.max_range, l.timestamp, l.laser_pose.x,
        l.laser_pose.y, l.laser_pose.theta, l.robot_pose.x, l.robot_pose.y, l.robot_pose.theta}) {
    if (!std::isfinite(v)) fail(l.message + ": expected finite angles, range limit, poses, time");
  }
  l.has_timestamp = l.timestamp != 0.0;
  l.fov_from_log = true;
  l.forward_offset = 0.0;
}

void CarmenReader::parseRawLaser(CarmenRecord& record, int index) {
  const char* layout =
      "laser_type start_angle fov resolution max_range accuracy remission_mode n ranges[n] m "
      "remissions[m] ipc_timestamp host logger_timestamp";
  record.kind = CarmenRecord::Kind::kLaser;
  CarmenLaser& l = record.laser;
  l.message = "RAWLASER" + std::to_string(index);
  l.sensor = sensorName(l.message, ("raw" + std::to_string(index)).c_str());
  const std::size_t k = parseLaserScan(l, 3, layout);
  l.timestamp = number(k, "the ipc timestamp");
  l.host = rawToken(k + 1);
  l.logger_timestamp = tokens_.size() > k + 2 ? number(k + 2, "the logger timestamp") : 0.0;
  for (double v : {l.angle_min, l.fov, l.angle_increment, l.max_range, l.timestamp}) {
    if (!std::isfinite(v)) fail(l.message + ": expected finite angles, range limit and time");
  }
  l.has_timestamp = l.timestamp != 0.0;
  l.has_pose = false;
  l.laser_pose = l.robot_pose = CarmenPose{};
  l.tv = l.rv = 0.0;
  l.fov_from_log = true;
  l.forward_offset = 0.0;
}

void CarmenReader::parseOdometry(CarmenRecord& record) {
  expectTokens(10, "x y theta tv rv accel ipc_timestamp host logger_timestamp");
  record.kind = CarmenRecord::Kind::kOdometry;
  CarmenOdometry& o = record.odometry;
  o.pose = {number(1, "x"), number(2, "y"), number(3, "theta")};
  o.tv = number(4, "tv");
  o.rv = number(5, "rv");
  o.acceleration = number(6, "the acceleration");
  o.timestamp = number(7, "the ipc timestamp");
  o.host = rawToken(8);
  o.logger_timestamp = tokens_.size() > 9 ? number(9, "the logger timestamp") : 0.0;
  for (double v : {o.pose.x, o.pose.y, o.pose.theta, o.tv, o.rv, o.timestamp}) {
    if (!std::isfinite(v)) fail("ODOM: expected finite pose, velocities and timestamp");
  }
  o.has_timestamp = o.timestamp != 0.0;
}

void CarmenReader::applyParam(CarmenRecord& record) {
  if (tokens_.size() < 3) {
    fail("PARAM: expected 'PARAM name value [ipc_timestamp host logger_timestamp]', found " +
         std::to_string(tokens_.size()) + " tokens");
  }
  std::string name(tokens_[1].first, tokens_[1].second);
  std::string value(tokens_[2].first, tokens_[2].second);
  ++stats_.params;
  params_[name] = value;
  record.kind = CarmenRecord::Kind::kParam;
  record.param.name = name;
  record.param.value = value;
  double v = 0.0;
  bool numeric = parseDouble(value.data(), value.data() + value.size(), v) && std::isfinite(v);
  auto setIf = [&](const char* key, auto&& apply) {
    if (name != key) return;
    if (!numeric || v <= -1e6 || v >= 1e6) {
      warn("PARAM " + name + " has non-numeric value '" + value + "'; ignored");
      return;
    }
    bool angular =
        name.find("laser_fov") != std::string::npos || name.find("resolution") != std::string::npos;
    if (angular && v <= 0.0) {
      warn("PARAM " + name + " must be positive (degrees), got '" + value + "'; ignored");
      return;
    }
    apply();
  };
  setIf("robot_frontlaser_offset", [&] { offset_[0] = v; });
  setIf("robot_rearlaser_offset", [&] { offset_[1] = v; });
  setIf("laser_front_laser_fov", [&] { fov_deg_[0] = v; });
  setIf("laser_rear_laser_fov", [&] { fov_deg_[1] = v; });
  setIf("laser_front_laser_resolution", [&] { resolution_deg_[0] = v; });
  setIf("laser_rear_laser_resolution", [&] { resolution_deg_[1] = v; });
}

}  // namespace io
}  // namespace plugslam
