#pragma once
// Streaming reader for CARMEN logs (plain text, gzip or bzip2): FLASER/RLASER (old format),
// ROBOTLASER1/2, RAWLASER1-4, ODOM and PARAM lines. Plain format code: no dependence on the plugin
// interfaces.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace plugslam {
namespace io {

/// What a reader does with a malformed record: throw ParseError, or warn, count and continue.
enum class ErrorPolicy { kStrict, kSkip };

/// A warning a reader reports instead of throwing (skip policy, or a non-fatal oddity).
struct ReaderWarning {
  std::string file;     ///< path of the file being read
  std::size_t line{0};  ///< 1-based line (0 when not line-based)
  std::string message;  ///< what was wrong and what was expected
};

/// Receives warnings; called synchronously from next().
using WarningCallback = std::function<void(const ReaderWarning&)>;

/// A planar pose x, y (metres), theta (radians) as logged.
struct CarmenPose {
  double x{0.0};
  double y{0.0};
  double theta{0.0};
};

/// One laser scan from a FLASER, RLASER, ROBOTLASERn or RAWLASERn line.
struct CarmenLaser {
  std::string message;             ///< message kind as logged ("FLASER", "ROBOTLASER1", ...)
  std::string sensor;              ///< sensor name ("front", "rear", ... or the caller's mapping)
  double timestamp{0.0};           ///< ipc timestamp (seconds; 0 in some logs = unknown)
  double logger_timestamp{0.0};    ///< logger timestamp (seconds), 0 if absent
  bool has_timestamp{false};       ///< false when the logged timestamp is 0 (unknown)
  bool time_backwards{false};      ///< timestamp earlier than an earlier scan of this sensor
  std::string host;                ///< ipc host name
  int laser_type{0};               ///< CARMEN laser type (0 when the format does not log it)
  double angle_min{0.0};           ///< angle of the first beam (rad, laser frame)
  double angle_increment{0.0};     ///< angle between beams (rad)
  double fov{0.0};                 ///< field of view (rad), as logged or as guessed
  double max_range{0.0};           ///< maximum range (m); readings >= max_range are no return
  double accuracy{0.0};            ///< logged range accuracy (m), 0 if not logged
  int remission_mode{0};           ///< logged remission mode, 0 if not logged
  bool fov_from_log{false};        ///< angles came from the line (ROBOTLASER/RAWLASER) or PARAMs
  std::vector<double> ranges;      ///< metres; NaN/inf/<=0 kept as logged = no return
  std::vector<double> remissions;  ///< remission values, empty for old formats
  bool has_pose{false};            ///< RAWLASER lines have no poses
  CarmenPose laser_pose;           ///< laser pose in the world/odom frame, as logged
  CarmenPose robot_pose;           ///< robot pose (odometry) as logged
  double tv{0.0};                  ///< translational velocity (ROBOTLASER only)
  double rv{0.0};                  ///< rotational velocity (ROBOTLASER only)
  double forward_offset{0.0};      ///< PARAM robot_{front,rear}laser_offset (m) for old formats
};

/// One ODOM line.
struct CarmenOdometry {
  CarmenPose pose;               ///< odometry pose
  double tv{0.0};                ///< translational velocity (m/s)
  double rv{0.0};                ///< rotational velocity (rad/s)
  double acceleration{0.0};      ///< logged acceleration
  double timestamp{0.0};         ///< ipc timestamp (seconds; 0 = unknown)
  double logger_timestamp{0.0};  ///< logger timestamp, 0 if absent
  bool has_timestamp{false};     ///< false when the logged timestamp is 0 (unknown)
  bool time_backwards{false};    ///< timestamp earlier than an earlier ODOM line
  std::string host;              ///< ipc host name
};

/// One PARAM line.
struct CarmenParam {
  std::string name;   ///< parameter name, e.g. robot_frontlaser_offset
  std::string value;  ///< parameter value as logged
};

/// One record of a CARMEN log; only the member named by kind is filled.
struct CarmenRecord {
  /// Which member holds the record.
  enum class Kind { kLaser, kOdometry, kParam };
  Kind kind{Kind::kLaser};  ///< which member is valid
  std::size_t line{0};      ///< 1-based line in the (decompressed) log
  CarmenLaser laser;        ///< valid when kind == kLaser
  CarmenOdometry odometry;  ///< valid when kind == kOdometry
  CarmenParam param;        ///< valid when kind == kParam
};

/// Options of CarmenReader.
struct CarmenReaderOptions {
  /// Malformed lines: throw ParseError (strict) or warn through on_warning and skip (skip).
  ErrorPolicy policy{ErrorPolicy::kStrict};
  /// Timestamps going backwards within a stream; unset = same as policy. kSkip warns and flags
  /// the record (it is still returned). The GMapping-corrected logs need kSkip here.
  std::optional<ErrorPolicy> time_policy;
  /// Receives every warning (skipped lines, backwards time, empty scans, truncated gzip or bzip2).
  WarningCallback on_warning;
  /// Emit PARAM lines as records (they are always applied to the reader's state).
  bool emit_params{false};
  /// Maximum range of old-format scans (FLASER/RLASER), which do not log it (CARMEN uses 80 m).
  double old_format_max_range{80.0};
  /// Sensor name per message kind ("FLASER" -> "front"); kinds not listed keep the defaults
  /// (FLASER, ROBOTLASER1: front; RLASER, ROBOTLASER2: rear; RAWLASERn: rawn).
  std::map<std::string, std::string> sensor_names;
  /// Lines longer than this are malformed (guards against binary garbage without newlines).
  std::size_t max_line_bytes{std::size_t{1} << 24};
};

/// Counters of one read, for reports and tests.
struct CarmenReaderStats {
  std::size_t lines{0};                      ///< lines read
  std::size_t lasers{0};                     ///< laser records returned
  std::size_t odometry{0};                   ///< ODOM records returned
  std::size_t params{0};                     ///< PARAM lines applied
  std::size_t comments{0};                   ///< '#' lines and blank lines
  std::size_t unknown{0};                    ///< lines of unknown message kinds (skipped)
  std::size_t malformed{0};                  ///< malformed lines skipped (skip policy)
  std::size_t empty_scans{0};                ///< laser lines with zero beams (skipped)
  std::size_t time_backwards{0};             ///< records flagged for backwards timestamps
  std::size_t warnings{0};                   ///< warnings issued
  std::map<std::string, std::size_t> kinds;  ///< lines per message kind, known or not
  bool compressed{false};                    ///< the file is gzip or bzip2
  std::string compression;                   ///< "gzip", "bzip2" or empty (plain text)
  bool truncated{false};                     ///< compressed stream ended early (skip policy)
};

/// Streaming CARMEN log reader: one record per next() call, in file order.
class CarmenReader {
 public:
  /// Opens path (plain text, gzip or bzip2, by magic bytes, whatever the extension); throws
  /// InputError naming a missing file.
  explicit CarmenReader(const std::string& path, CarmenReaderOptions options = {});
  /// Reads plain text held in memory (no decompression); name stands for the path in messages. For
  /// fuzzers and tests.
  static std::unique_ptr<CarmenReader> fromText(std::string name, std::string text,
                                                CarmenReaderOptions options = {});
  ~CarmenReader();
  CarmenReader(const CarmenReader&) = delete;
  CarmenReader& operator=(const CarmenReader&) = delete;

  /// Reads the next laser, odometry (or PARAM, if emitted) record; false at end of file.
  bool next(CarmenRecord& record);

  /// PARAM values seen so far (name -> value).
  const std::map<std::string, std::string>& params() const { return params_; }
  /// Counters so far.
  const CarmenReaderStats& stats() const { return stats_; }
  /// The path being read.
  const std::string& path() const { return path_; }

 private:
  class Source;
  CarmenReader(std::string name, std::string text, CarmenReaderOptions options);
  bool readLine();
  bool parseLine(CarmenRecord& record);
  void parseOldLaser(CarmenRecord& record, bool rear);
  void parseRobotLaser(CarmenRecord& record, int index);
  void parseRawLaser(CarmenRecord& record, int index);
  /// Reads the scan both ROBOTLASER and RAWLASER start with (laser type .. remissions), checking
  /// that `trailing` more tokens follow; returns the index of the first of those.
  std::size_t parseLaserScan(CarmenLaser& l, std::size_t trailing, const char* layout);
  void parseOdometry(CarmenRecord& record);
  void applyParam(CarmenRecord& record);
  void expectTokens(std::size_t count, const char* layout) const;
  double number(std::size_t index, const char* what) const;
  std::size_t count(std::size_t index, const char* what) const;
  int smallInt(std::size_t index, const char* what) const;
  std::string token(std::size_t index) const;  // shortened and sanitised, for messages
  std::string rawToken(std::size_t index) const;
  void fail(const std::string& message) const;
  void warn(const std::string& message);
  void checkTime(const std::string& stream, double t, bool& backwards);
  std::string sensorName(const std::string& kind, const char* fallback) const;

  std::string path_;
  CarmenReaderOptions options_;
  std::unique_ptr<Source> source_;
  std::string line_;
  std::vector<std::pair<const char*, const char*>> tokens_;
  std::size_t line_number_{0};
  std::map<std::string, std::string> params_;
  std::map<std::string, double> last_time_;
  // Cached laser PARAMs, index 0 = front, 1 = rear.
  std::optional<double> fov_deg_[2];
  std::optional<double> resolution_deg_[2];
  double offset_[2]{0.0, 0.0};
  bool last_line_unterminated_{false};
  CarmenReaderStats stats_;
};

/// True when a range reading is a return: finite, > 0 and < max_range.
bool isRangeReturn(double range, double max_range);

}  // namespace io
}  // namespace plugslam
