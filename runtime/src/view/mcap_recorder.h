#pragma once
// `--record FILE.mcap`: every message of the viewer stream, at full rate, on the same channels and
// with the same JSON schemas as the live server, in an indexed MCAP file (chunks, message indexes,
// summary) that Foxglove and Lichtblick seek in.
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "plugslam/mcap/writer.h"
#include "view/view_hub.h"

namespace plugslam::runtime {

/// A hub receiver writing an MCAP file; close() (or the destructor) finishes it.
class McapRecorder final : public ViewReceiver {
 public:
  /// Creates `path` (InputError when it cannot be written) and attaches to `hub`.
  McapRecorder(ViewHub& hub, const std::string& path);
  ~McapRecorder() override;
  /// Detaches and writes the summary; throws when the file could not be completed.
  void close();
  /// Messages written so far.
  uint64_t messages() const;
  /// The file's path.
  const std::string& path() const { return path_; }

  void channelAdded(const ViewChannel& channel) override;
  void deliver(const ViewMessage& message) override;
  bool wants(int) const override { return true; }
  bool fullRate() const override { return true; }

 private:
  ViewHub& hub_;
  std::string path_;
  mutable std::mutex mutex_;
  std::unique_ptr<mcap::Writer> writer_;
  std::map<int, uint16_t> channels_;  // hub channel id -> MCAP channel id
  std::string error_;                 // the first write failure
  bool attached_ = false;
};

}  // namespace plugslam::runtime
