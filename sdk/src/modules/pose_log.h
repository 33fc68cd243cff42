#pragma once
// An append-only log of stamped poses whose memory does not grow with the run: past a chunk of
// records it moves them to an anonymous temporary file and reads them back on demand. The
// pipeline keeps one pose per frame for its outputs (a corrected trajectory needs every frame),
// so without this a localization run of days would grow by ~150 bytes per frame. The chunk is
// small (1024 records, 112 KiB) so that filling it is not itself a growth a soak can see: at
// 16384 records the two logs of a run added 3.5 MiB over the first 16k frames (+19 % of a building
// log's localization RSS); one write per 1024 frames costs nothing measurable.
#include <Eigen/Geometry>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <vector>

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

/// Append-only, disk-backed sequence of (stamp, key, pose) records.
class PoseLog {
 public:
  /// One record: the frame's time, a key (the local map's id, or 0) and the pose.
  struct Entry {
    double stamp = 0.0;
    int64_t key = 0;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  };

  /// Records kept in memory by default before they move to the file.
  static constexpr std::size_t kDefaultChunk = 1024;
  /// `chunk`: records kept in memory before they move to the file.
  explicit PoseLog(std::size_t chunk = kDefaultChunk);
  ~PoseLog();
  PoseLog(const PoseLog&) = delete;
  PoseLog& operator=(const PoseLog&) = delete;

  /// Appends a record.
  void push_back(const Entry& e);
  /// Calls `f` on every record in order.
  void forEach(const std::function<void(const Entry&)>& f) const;
  /// Number of records.
  std::size_t size() const { return spilled_ + tail_.size(); }
  /// True when no record was appended.
  bool empty() const { return size() == 0; }
  /// Records currently in memory (the rest are in the file).
  std::size_t inMemory() const { return tail_.size(); }

 private:
  // On-disk form: the pose's 3x4 matrix as is (a quaternion would not give the poses back
  // bit for bit, and ground truth must stay exact).
  struct Packed {
    double stamp;
    int64_t key;
    double m[12];
  };
  static Packed pack(const Entry& e);
  static Entry unpack(const Packed& p);
  void spill();

  std::size_t chunk_;
  std::vector<Packed> tail_;
  std::FILE* file_ = nullptr;
  std::size_t spilled_ = 0;
  bool file_failed_ = false;  // no temporary file could be used: everything stays in memory
};

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
