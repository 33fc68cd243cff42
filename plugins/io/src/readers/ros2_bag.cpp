#include "readers/ros2_bag.h"

#include <spdlog/spdlog.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include "plugslam/errors.h"
#include "plugslam/mcap/reader.h"
#include "plugslam/yaml_load.h"

namespace plugslam {
namespace io {

namespace fs = std::filesystem;

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string storageOf(const std::string& file) {
  if (endsWith(file, ".mcap")) return "mcap";
  if (endsWith(file, ".db3")) return "sqlite3";
  return "";
}

}  // namespace

// One storage file being read.
struct Ros2Bag::File {
  virtual ~File() = default;
  virtual bool next(Ros2Message& m) = 0;
};

namespace {

class McapFile : public Ros2Bag::File {
 public:
  McapFile(const std::string& path, const std::set<std::string>& topics) : path_(path) {
    mcap::ReaderOptions options;
    options.topics = topics;
    reader_ = std::make_unique<mcap::Reader>(path, options);
  }
  bool next(Ros2Message& m) override {
    mcap::ReadMessage r;
    if (!reader_->next(r)) return false;
    m.topic = r.channel->topic;
    m.type = r.schema ? r.schema->name : std::string();
    m.encoding = r.channel->message_encoding;
    m.log_time = r.header.log_time;
    m.data = std::move(r.data);
    m.file = path_;
    m.offset = r.offset;
    return true;
  }
  static std::vector<BagTopic> topics(const std::string& path) {
    mcap::Reader reader(path);
    std::map<uint16_t, std::size_t> counts;
    if (reader.statistics()) {
      for (const auto& [id, n] : reader.statistics()->channel_message_counts) counts[id] = n;
    } else {
      // No summary: count by reading (channels are learnt on the way).
      mcap::ReadMessage m;
      while (reader.next(m)) ++counts[m.channel->id];
    }
    std::vector<BagTopic> out;
    for (const auto& [id, c] : reader.channels()) {
      const auto s = reader.schemas().find(c.schema_id);
      out.push_back({c.topic, s != reader.schemas().end() ? s->second.name : "", counts[id]});
    }
    return out;
  }

 private:
  std::string path_;
  std::unique_ptr<mcap::Reader> reader_;
};

class Sqlite {
 public:
  explicit Sqlite(const std::string& path) : path_(path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      db_ = nullptr;
      throw InputError("cannot open the ROS 2 database '" + path + "': " + why);
    }
  }
  ~Sqlite() {
    sqlite3_finalize(stmt_);
    sqlite3_close(db_);
  }
  Sqlite(const Sqlite&) = delete;
  Sqlite& operator=(const Sqlite&) = delete;
  [[noreturn]] void fail(const std::string& what) const {
    throw ParseError(path_, 0, what + ": " + sqlite3_errmsg(db_) +
                                   " (not a rosbag2 SQLite database, or a damaged one)");
  }
  void prepare(const std::string& sql) {
    sqlite3_finalize(stmt_);
    stmt_ = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) fail(sql);
  }
  // True while there are rows.
  bool step(const char* what) {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) fail(what);
    return false;
  }
  std::string text(int col) const {
    const auto* p = sqlite3_column_text(stmt_, col);
    return p ? reinterpret_cast<const char*>(p) : "";
  }
  int64_t integer(int col) const { return sqlite3_column_int64(stmt_, col); }
  std::string blob(int col) const {
    const void* p = sqlite3_column_blob(stmt_, col);
    const int n = sqlite3_column_bytes(stmt_, col);
    return p ? std::string(static_cast<const char*>(p), static_cast<std::size_t>(n)) : "";
  }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
};

struct DbTopic {
  std::string name, type, format;
};

std::map<int64_t, DbTopic> dbTopics(Sqlite& db) {
  db.prepare("SELECT id, name, type, serialization_format FROM topics");
  std::map<int64_t, DbTopic> out;
  while (db.step("reading the topics table")) {
    out[db.integer(0)] = {db.text(1), db.text(2), db.text(3)};
  }
  return out;
}

class SqliteFile : public Ros2Bag::File {
 public:
  SqliteFile(const std::string& path, const std::set<std::string>& topics)
      : path_(path), db_(path) {
    topics_ = dbTopics(db_);
    std::string ids;
    for (const auto& [id, t] : topics_) {
      if (!topics.empty() && !topics.count(t.name)) continue;
      ids += (ids.empty() ? "" : ",") + std::to_string(id);
    }
    // rosbag2 itself plays in timestamp order; the row id keeps equal stamps in recording order.
    db_.prepare("SELECT topic_id, timestamp, data, id FROM messages WHERE topic_id IN (" + ids +
                ") ORDER BY timestamp, id");
  }
  bool next(Ros2Message& m) override {
    if (!db_.step("reading the messages table")) return false;
    const auto t = topics_.find(db_.integer(0));
    if (t == topics_.end()) return next(m);  // not selected: cannot happen with the IN list
    m.topic = t->second.name;
    m.type = t->second.type;
    m.encoding = t->second.format;
    m.log_time = static_cast<std::uint64_t>(db_.integer(1));
    m.data = db_.blob(2);
    m.file = path_;
    m.offset = static_cast<std::uint64_t>(db_.integer(3));
    return true;
  }
  static std::vector<BagTopic> topics(const std::string& path) {
    Sqlite db(path);
    auto names = dbTopics(db);
    db.prepare("SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
    std::map<int64_t, std::size_t> counts;
    while (db.step("counting messages")) counts[db.integer(0)] = static_cast<std::size_t>(db.integer(1));
    std::vector<BagTopic> out;
    for (const auto& [id, t] : names) out.push_back({t.name, t.type, counts[id]});
    return out;
  }

 private:
  std::string path_;
  Sqlite db_;
  std::map<int64_t, DbTopic> topics_;
};

}  // namespace

Ros2Bag::Ros2Bag(std::string path) : path_(std::move(path)) {
  std::error_code ec;
  if (!fs::exists(path_, ec)) throw InputError("ROS 2 bag '" + path_ + "' does not exist");
  if (fs::is_directory(path_, ec)) {
    const fs::path metadata = fs::path(path_) / "metadata.yaml";
    if (fs::exists(metadata, ec)) {
      // A value of the wrong kind (a map where a name belongs) is the file's fault, at its line.
      try {
        const YAML::Node info = loadYamlFile(metadata.string())["rosbag2_bagfile_information"];
        if (!info) {
          throw ParseError(metadata.string(), 0, "no rosbag2_bagfile_information (not rosbag2's)");
        }
        const std::string mode = info["compression_mode"].as<std::string>("");
        if (!mode.empty() && mode != "NONE") {
          throw InputError("ROS 2 bag '" + path_ + "' is compressed per " + mode + " (" +
                           info["compression_format"].as<std::string>("") +
                           "); only chunk-compressed MCAP is read: `ros2 bag decompress` it first");
        }
        storage_ = info["storage_identifier"].as<std::string>("");
        for (const auto& f : info["relative_file_paths"]) {
          // Older rosbag2 wrote paths relative to the folder's parent.
          fs::path p = fs::path(path_) / f.as<std::string>();
          if (!fs::exists(p, ec)) p = fs::path(path_).parent_path() / f.as<std::string>();
          if (!fs::exists(p, ec)) {
            throw InputError(metadata.string() + ": storage file '" + f.as<std::string>() +
                             "' is not in the bag's folder");
          }
          files_.push_back(p.string());
        }
        if (info["topics_with_message_count"]) {
          std::vector<BagTopic> topics;
          for (const auto& t : info["topics_with_message_count"]) {
            topics.push_back({t["topic_metadata"]["name"].as<std::string>(""),
                              t["topic_metadata"]["type"].as<std::string>(""),
                              t["message_count"].as<std::size_t>(0)});
          }
          topics_ = std::move(topics);
        }
      } catch (const YAML::Exception& e) {
        throw ParseError(metadata.string(), e.mark.line >= 0 ? e.mark.line + 1 : 0, e.msg);
      }
    } else {
      // No metadata.yaml (the recorder was killed before writing it): its storage files in order.
      for (fs::directory_iterator it(path_, ec), end; it != end; it.increment(ec)) {
        if (!storageOf(it->path().string()).empty()) files_.push_back(it->path().string());
      }
      std::sort(files_.begin(), files_.end());
      if (files_.empty()) {
        throw InputError("'" + path_ + "' is a folder with neither metadata.yaml nor .mcap/.db3 "
                         "files: not a ROS 2 bag");
      }
      spdlog::warn("ROS 2 bag '{}' has no metadata.yaml: reading its {} storage file(s) by name",
                   path_, files_.size());
      storage_ = storageOf(files_.front());
    }
  } else {
    storage_ = storageOf(path_);
    if (storage_.empty()) {
      throw InputError("'" + path_ + "' is not a ROS 2 bag: expected a rosbag2 folder, an .mcap "
                       "or a .db3 file");
    }
    files_.push_back(path_);
  }
  if (storage_ != "mcap" && storage_ != "sqlite3") {
    throw InputError("ROS 2 bag '" + path_ + "': storage '" + storage_ +
                     "' is not read (known: mcap, sqlite3)");
  }
  if (files_.empty()) throw InputError("ROS 2 bag '" + path_ + "' lists no storage file");
}

Ros2Bag::~Ros2Bag() = default;

const std::vector<BagTopic>& Ros2Bag::topics() const {
  if (!topics_) {
    std::map<std::string, BagTopic> merged;
    for (const auto& f : files_) {
      for (const auto& t : storageOf(f) == "sqlite3" ? SqliteFile::topics(f) : McapFile::topics(f)) {
        auto& m = merged[t.topic];
        m.topic = t.topic;
        if (m.type.empty()) m.type = t.type;
        m.count += t.count;
      }
    }
    topics_.emplace();
    for (auto& [name, t] : merged) topics_->push_back(std::move(t));
  }
  return *topics_;
}

std::unique_ptr<Ros2Bag::File> Ros2Bag::openFile(const std::string& file,
                                                  const std::set<std::string>& topics) {
  if (storageOf(file) == "sqlite3") return std::make_unique<SqliteFile>(file, topics);
  return std::make_unique<McapFile>(file, topics);
}

void Ros2Bag::open(std::set<std::string> topics) {
  wanted_ = std::move(topics);
  file_index_ = 0;
  current_.reset();
}

bool Ros2Bag::next(Ros2Message& message) {
  for (;;) {
    if (!current_) {
      if (file_index_ >= files_.size()) return false;
      current_ = openFile(files_[file_index_++], wanted_);
    }
    if (current_->next(message)) return true;
    current_.reset();
  }
}

std::uint64_t Ros2Bag::bytes() const {
  std::uint64_t n = 0;
  std::error_code ec;
  for (const auto& f : files_) {
    const auto s = fs::file_size(f, ec);
    if (!ec) n += s;
  }
  return n;
}

}  // namespace io
}  // namespace plugslam
