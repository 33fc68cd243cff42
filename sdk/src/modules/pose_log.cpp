#include "pose_log.h"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstring>

namespace plugslam {
inline namespace abi_v1 {
namespace detail {

PoseLog::PoseLog(std::size_t chunk) : chunk_(chunk > 0 ? chunk : 1) { tail_.reserve(chunk_); }

PoseLog::~PoseLog() {
  if (file_) std::fclose(file_);  // tmpfile() files vanish when closed
}

PoseLog::Packed PoseLog::pack(const Entry& e) {
  Packed p;
  p.stamp = e.stamp;
  p.key = e.key;
  Eigen::Map<Eigen::Matrix<double, 3, 4>>(p.m) = e.pose.matrix().topRows<3>();
  return p;
}

PoseLog::Entry PoseLog::unpack(const Packed& p) {
  Entry e;
  e.stamp = p.stamp;
  e.key = p.key;
  e.pose.matrix().topRows<3>() = Eigen::Map<const Eigen::Matrix<double, 3, 4>>(p.m);
  return e;
}

void PoseLog::push_back(const Entry& e) {
  tail_.push_back(pack(e));
  if (tail_.size() >= chunk_ && !file_failed_) spill();
}

void PoseLog::spill() {
  if (!file_) {
    file_ = std::tmpfile();
    if (!file_) {
      file_failed_ = true;
      spdlog::warn("no temporary file for the trajectory record ({}); it stays in memory",
                   std::strerror(errno));
      return;
    }
  }
  // Appends at the end even after forEach() read from the start.
  if (std::fseek(file_, 0, SEEK_END) != 0 ||
      std::fwrite(tail_.data(), sizeof(Packed), tail_.size(), file_) != tail_.size() ||
      std::fflush(file_) != 0) {
    // The records already in the file stay valid; from now on everything stays in memory.
    file_failed_ = true;
    spdlog::warn("cannot extend the trajectory record's temporary file ({}); it stays in memory",
                 std::strerror(errno));
    return;
  }
  spilled_ += tail_.size();
  tail_.clear();
}

void PoseLog::forEach(const std::function<void(const Entry&)>& f) const {
  if (file_ && spilled_ > 0) {
    std::vector<Packed> buffer(chunk_);
    if (std::fseek(file_, 0, SEEK_SET) != 0)
      throw std::runtime_error("cannot rewind the trajectory record's temporary file");
    std::size_t left = spilled_;
    while (left > 0) {
      const std::size_t n = std::fread(buffer.data(), sizeof(Packed), std::min(left, chunk_), file_);
      if (n == 0) throw std::runtime_error("the trajectory record's temporary file is truncated");
      for (std::size_t i = 0; i < n; ++i) f(unpack(buffer[i]));
      left -= n;
    }
  }
  for (const Packed& p : tail_) f(unpack(p));
}

}  // namespace detail
}  // namespace abi_v1
}  // namespace plugslam
