#pragma once
// Reader for ROS1 bag files (format v2.0), read directly: records, chunks (none, bz2, lz4),
// connections and message data. No ROS dependency. Index records are not needed: chunks are read
// in file order and messages are returned in time order.
#include <cstddef>
#include <cstdint>
#include <istream>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace plugslam {
namespace io {

/// A ROS time stamp (seconds and nanoseconds since the epoch).
struct RosTime {
  std::uint32_t sec{0};   ///< seconds
  std::uint32_t nsec{0};  ///< nanoseconds
  /// Seconds as a double.
  double toSec() const { return sec + 1e-9 * nsec; }
  /// Total nanoseconds, for exact ordering.
  std::uint64_t toNsec() const { return std::uint64_t{sec} * 1000000000ull + nsec; }
};

/// One bag connection: a topic with its message type.
struct RosbagConnection {
  std::uint32_t id{0};             ///< connection id within the bag
  std::string topic;               ///< topic name, e.g. /scan
  std::string type;                ///< message type, e.g. sensor_msgs/LaserScan
  std::string md5sum;              ///< message definition checksum
  std::string message_definition;  ///< full message definition text
  std::string callerid;            ///< publishing node, if recorded
};

/// One message: raw ROS-serialized bytes plus where it came from.
struct RosbagMessage {
  const RosbagConnection* connection{nullptr};  ///< owned by the reader, valid while it lives
  RosTime time;                                 ///< record (receipt) time
  std::vector<std::uint8_t> data;               ///< serialized message
  std::uint64_t file_offset{0};  ///< offset of the enclosing record (chunk) in the file
  bool out_of_order{false};      ///< earlier than a message already returned
};

/// Per-topic summary of a bag.
struct RosbagTopicInfo {
  std::string topic;       ///< topic name
  std::string type;        ///< message type
  std::size_t count{0};    ///< number of messages
  double first_time{0.0};  ///< earliest record time (s)
  double last_time{0.0};   ///< latest record time (s)
};

/// Options of RosbagReader.
struct RosbagReaderOptions {
  /// Topics to return; empty = every topic.
  std::set<std::string> topics;
  /// Upper bound of one record's header or data and of a decompressed chunk (bytes).
  std::size_t max_record_bytes{std::size_t{1} << 31};
};

/// Counters of one read.
struct RosbagReaderStats {
  std::size_t chunks{0};                           ///< chunk records read
  std::size_t messages{0};                         ///< messages returned
  std::size_t filtered{0};                         ///< messages of other topics, not returned
  std::size_t out_of_order{0};                     ///< messages returned after a later one
  std::map<std::string, std::size_t> compression;  ///< chunks per compression kind
};

/// Streaming ROS1 bag v2.0 reader; next() returns messages in record-time order.
class RosbagReader {
 public:
  /// Opens path and checks the "#ROSBAG V2.0" magic; InputError if missing, ParseError if not a
  /// bag.
  explicit RosbagReader(const std::string& path, RosbagReaderOptions options = {});
  /// Reads a bag held in memory; name stands for the path in messages. For fuzzers and tests.
  static std::unique_ptr<RosbagReader> fromBytes(std::string name, std::string bytes,
                                                 RosbagReaderOptions options = {});
  ~RosbagReader();
  RosbagReader(const RosbagReader&) = delete;
  RosbagReader& operator=(const RosbagReader&) = delete;

  /// Next message in time order; false at the end. Throws ParseError (line 0, byte offset in
  /// the message) on a corrupt or truncated bag.
  bool next(RosbagMessage& message);

  /// Connections seen so far, by id.
  const std::map<std::uint32_t, std::unique_ptr<RosbagConnection>>& connections() const {
    return connections_;
  }
  /// Counters so far.
  const RosbagReaderStats& stats() const { return stats_; }
  /// The path being read.
  const std::string& path() const { return path_; }

 private:
  struct Pending;
  struct Record;
  RosbagReader(std::string name, std::string bytes, RosbagReaderOptions options);
  void checkMagic();
  bool readTopRecord(Record& record);
  void loadChunk(const Record& record);
  void parseInner(const std::uint8_t* data, std::size_t size, std::uint64_t base);
  void addConnection(std::uint32_t id, const std::string& topic, const std::uint8_t* data,
                     std::size_t size, std::uint64_t offset);
  void addMessage(std::uint32_t conn, RosTime time, const std::uint8_t* data, std::size_t size,
                  std::uint64_t offset);
  static bool later(const std::unique_ptr<Pending>& a, const std::unique_ptr<Pending>& b);
  [[noreturn]] void fail(std::uint64_t offset, const std::string& message) const;

  std::string path_;
  RosbagReaderOptions options_;
  std::unique_ptr<std::istream> file_;
  std::uint64_t file_size_{0};
  std::uint64_t position_{0};
  bool at_end_{false};
  std::map<std::uint32_t, std::unique_ptr<RosbagConnection>> connections_;
  // Messages loaded but not returned, a min-heap on (time, sequence).
  std::vector<std::unique_ptr<Pending>> heap_;
  std::uint64_t sequence_{0};
  std::uint64_t watermark_ns_{0};  // messages up to this time may be returned
  std::uint64_t chunk_min_ns_{0};  // earliest message time in the record being loaded
  std::uint64_t last_returned_ns_{0};
  bool returned_any_{false};
  RosbagReaderStats stats_;
};

/// Reads a whole bag and lists its topics with types, counts and time spans.
std::vector<RosbagTopicInfo> summarizeRosbag(const std::string& path);

}  // namespace io
}  // namespace plugslam
