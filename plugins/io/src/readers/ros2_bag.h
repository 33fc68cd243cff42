#pragma once
// The storage of ROS 2 bags: a rosbag2 folder (metadata.yaml naming its MCAP or SQLite .db3
// files), a folder of such files without metadata.yaml (a recording cut short), or one bare
// .mcap or .db3 file. Messages come out as CDR bytes with their topic, type and log time; the
// MCAP files are read by the SDK's mcap::Reader, the .db3 files through SQLite.
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sources/bag_source.h"

namespace plugslam {
namespace io {

/// One serialized message of a ROS 2 bag.
struct Ros2Message {
  std::string topic;      ///< topic name
  std::string type;       ///< e.g. sensor_msgs/msg/LaserScan
  std::string encoding;   ///< serialization ("cdr")
  std::uint64_t log_time = 0;  ///< receipt time [ns]
  std::string data;       ///< serialized message
  std::string file;       ///< the storage file it is in
  std::uint64_t offset = 0;  ///< MCAP: byte offset of its record or chunk; .db3: row id
};

/// A ROS 2 bag; one pass at a time over the messages of chosen topics.
class Ros2Bag {
 public:
  /// Opens `path` (folder, .mcap or .db3); InputError when it is none of them or is missing,
  /// ParseError when a file is malformed.
  explicit Ros2Bag(std::string path);
  ~Ros2Bag();
  Ros2Bag(const Ros2Bag&) = delete;
  Ros2Bag& operator=(const Ros2Bag&) = delete;

  /// The bag's topics with types and message counts (from metadata.yaml, the MCAP summary or
  /// the database; a pass over an MCAP file without summary).
  const std::vector<BagTopic>& topics() const;
  /// Starts a pass over the messages of `topics` (empty = all), file after file.
  void open(std::set<std::string> topics);
  /// The next message of the pass; false at its end.
  bool next(Ros2Message& message);
  /// "mcap" or "sqlite3".
  const std::string& storage() const { return storage_; }
  /// The storage files, in reading order.
  const std::vector<std::string>& files() const { return files_; }
  /// Their total size [bytes].
  std::uint64_t bytes() const;

  struct File;

 private:
  std::unique_ptr<File> openFile(const std::string& file, const std::set<std::string>& topics);
  std::string path_;
  std::string storage_;
  std::vector<std::string> files_;
  mutable std::optional<std::vector<BagTopic>> topics_;
  std::set<std::string> wanted_;
  std::size_t file_index_ = 0;
  std::unique_ptr<File> current_;
};

}  // namespace io
}  // namespace plugslam
