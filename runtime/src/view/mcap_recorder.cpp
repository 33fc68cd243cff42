#include "view/mcap_recorder.h"

#include <spdlog/spdlog.h>

#include "plugslam/errors.h"
#include "plugslam/version.h"

namespace plugslam::runtime {

McapRecorder::McapRecorder(ViewHub& hub, const std::string& path) : hub_(hub), path_(path) {
  mcap::WriterOptions options;
  options.library = std::string("plugslam ") + PLUGSLAM_VERSION_STRING;
  writer_ = std::make_unique<mcap::Writer>(path, options);
  hub_.attach(this);
  attached_ = true;
}

McapRecorder::~McapRecorder() {
  try {
    close();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  }
}

void McapRecorder::close() {
  if (attached_) {
    hub_.flush();
    hub_.detach(this);
    attached_ = false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (!writer_) return;
  auto writer = std::move(writer_);
  writer->close();
  if (!error_.empty()) throw Error("recording '" + path_ + "' is incomplete: " + error_);
  spdlog::info("recorded {} messages in {}", writer->messages(), path_);
}

uint64_t McapRecorder::messages() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return writer_ ? writer_->messages() : 0;
}

void McapRecorder::channelAdded(const ViewChannel& channel) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!writer_ || channels_.count(channel.id)) return;
  try {
    const uint16_t schema = writer_->addSchema(channel.schema_name, "jsonschema", channel.schema);
    channels_[channel.id] = writer_->addChannel(schema, channel.topic, "json");
  } catch (const std::exception& e) {
    if (error_.empty()) error_ = e.what();
  }
}

void McapRecorder::deliver(const ViewMessage& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!writer_ || !error_.empty()) return;
  auto it = channels_.find(message.channel);
  if (it == channels_.end()) return;
  try {
    writer_->write(it->second, message.log_time, message.log_time, message.payload->data(),
                   message.payload->size());
  } catch (const std::exception& e) {
    // A full disk must not stop the run: the recording stops, the run goes on, and close() says.
    error_ = e.what();
    spdlog::error("recording stopped: {}", e.what());
  }
}

}  // namespace plugslam::runtime
