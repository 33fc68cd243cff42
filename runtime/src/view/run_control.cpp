#include "view/run_control.h"

#include <spdlog/spdlog.h>

#include <boost/filesystem.hpp>

#include "editor/config_editor.h"
#include "config_builder.h"
#include "plugslam/errors.h"
#include "shell/module_paths.h"
#include "view/parameters.h"

namespace plugslam::runtime {

ViewControl::~ViewControl() = default;

namespace {

// At most this many settings wait for validation: each rebuilds the whole config, and a client
// that sends more is only filling a queue.
constexpr size_t kMaxPendingValidations = 16;

std::string relativeUnder(const std::string& path) {
  namespace fs = boost::filesystem;
  const fs::path p(path);
  if (path.empty() || p.is_absolute()) return "";
  for (const auto& part : p)
    if (part == "..") return "";
  return p.lexically_normal().string();
}

}  // namespace

RunControl::RunControl(RunConfig& run, ConfigDocument& doc, PluginManager& plugins,
                       std::string out_dir, ViewStream& stream, SaveSession save_session,
                       std::function<bool()> interrupted, std::string* config_yaml,
                       bool start_paused)
    : run_(run),
      doc_(doc),
      plugins_(plugins),
      out_dir_(std::move(out_dir)),
      stream_(stream),
      save_session_(std::move(save_session)),
      interrupted_(std::move(interrupted)),
      config_yaml_(config_yaml),
      services_(standardServices(&run)),
      paused_(start_paused),
      // A setting waiting when the run ends would be applied to nothing: it is dropped.
      validator_(kMaxPendingValidations, "viewer: parameter validation failed",
                 JobThread::OnStop::kDropWaiting) {
  if (paused_) stream_.setState("paused");
}

RunControl::~RunControl() { shutdown(); }

void RunControl::shutdown() {
  validator_.stop();
  std::deque<Command> left;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ended_ = true;
    left.swap(queue_);
  }
  cv_.notify_all();
  CallDone step;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    step = std::move(step_done_);
    step_done_ = nullptr;
  }
  std::lock_guard<std::mutex> one(after_end_mutex_);
  for (auto& c : left) c(nullptr);
  if (step) step(false, "the run has ended");
}

std::string RunControl::configYaml() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return resolvedYaml(doc_);
}

bool RunControl::enqueue(Command command) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (ended_) {
    // Nothing runs any more: the command may touch the tree right here (one at a time).
    lock.unlock();
    std::lock_guard<std::mutex> one(after_end_mutex_);
    command(nullptr);
    return false;
  }
  queue_.push_back(std::move(command));
  lock.unlock();
  cv_.notify_all();
  return true;
}

void RunControl::runQueued(std::unique_lock<std::mutex>& lock, Execution* execution) {
  while (!queue_.empty()) {
    Command c = std::move(queue_.front());
    queue_.pop_front();
    lock.unlock();
    try {
      c(execution);
    } catch (const std::exception& e) {
      spdlog::warn("viewer request failed: {}", e.what());
    }
    lock.lock();
  }
}

std::vector<foxglove::Service> RunControl::services() { return services_; }

void RunControl::getParameters(std::vector<std::string> names, ParametersDone done) {
  enqueue([this, names = std::move(names), done = std::move(done)](Execution*) {
    std::vector<std::string> errors;
    auto values = listParameters(run_, names, errors);
    done(std::move(values), std::move(errors));
  });
}

void RunControl::setParameters(std::vector<foxglove::ParameterAssignment> assignments,
                               ParametersDone done) {
  std::vector<std::string> names;
  for (const auto& a : assignments) names.push_back(a.name);
  auto reply = [this, names, done](std::vector<std::string> errors) {
    enqueue([this, names, done, errors = std::move(errors)](Execution*) mutable {
      auto values = listParameters(run_, names, errors);
      done(std::move(values), std::move(errors));
    });
  };
  // What cannot change mid-run is refused at once; the rest is validated off the run's thread.
  std::vector<std::string> errors;
  std::vector<foxglove::ParameterAssignment> live;
  for (const auto& a : assignments) {
    try {
      const std::string why = liveRefusal(run_, a.name);
      if (why.empty()) {
        live.push_back(a);
      } else {
        errors.push_back("'" + a.name + "' cannot change during a run: " + why);
      }
    } catch (const std::exception& e) {
      errors.push_back(e.what());
    }
  }
  if (live.empty()) return reply(std::move(errors));
  const auto posted = validator_.post([this, live, errors, reply]() mutable {
    // Exactly `--set`: the overrides applied to a copy of the document, the whole run rebuilt.
    ConfigDocument copy;
    {
      std::lock_guard<std::mutex> guard(mutex_);
      copy = doc_;
      copy.root.reset(YAML::Clone(doc_.root));
    }
    try {
      for (const auto& a : live) applyOverride(copy, a.name + "=" + a.value);
      buildRun(copy, plugins_);
    } catch (const std::exception& e) {
      errors.push_back(e.what());
      return reply(std::move(errors));
    }
    enqueue([this, live, errors, reply](Execution*) mutable {
      for (const auto& a : live) {
        try {
          applyLive(run_, a.name, a.value);
          std::lock_guard<std::mutex> guard(mutex_);
          applyOverride(doc_, a.name + "=" + a.value);
          // Sessions saved from now on carry the new value (this is the run's thread).
          if (config_yaml_) *config_yaml_ = resolvedYaml(doc_);
          spdlog::info("viewer: {} = {}", a.name, a.value);
        } catch (const std::exception& e) {
          errors.push_back(e.what());
        }
      }
      reply(std::move(errors));
    });
  });
  if (posted == JobThread::Posted::kFull) {
    errors.push_back("too many parameter changes waiting for validation; try again");
    reply(std::move(errors));
  }
}

void RunControl::call(const std::string& service, const std::string& request, CallDone done) {
  if (editor::ConfigEditor::handles(service)) {
    // Off the run's thread and the server's: validation runs `plugslam validate` (a process).
    auto job = [this, service, request, done] {
      try {
        std::string name;
        {
          std::lock_guard<std::mutex> guard(mutex_);
          name = doc_.file;
        }
        const editor::ConfigEditor ed(editor::editorRoot(), configYaml(), name);
        done(true, ed.call(service, request));
      } catch (const std::exception& e) {
        done(false, e.what());
      }
    };
    switch (validator_.post(job)) {
      case JobThread::Posted::kQueued:
        return;
      case JobThread::Posted::kFull:
        return done(false, "too many requests waiting; try again");
      case JobThread::Posted::kStopped:  // the run has ended: nobody else will answer
        return job();
    }
    return;
  }
  ServiceRequest r;
  if (!parseServiceRequest(request, r, done)) return;
  auto frameText = [](Execution* e) { return std::to_string(e ? e->frames() : 0); };
  if (service == "pause") {
    enqueue([this, done, frameText](Execution* e) {
      if (!e) return done(false, "the run has ended");
      std::unique_lock<std::mutex> lock(mutex_);
      if (paused_) return done(false, "already paused at frame " + frameText(e));
      paused_ = true;
      budget_ = 0;
      lock.unlock();
      stream_.setState("paused");
      done(true, "paused at frame " + frameText(e));
    });
  } else if (service == "resume") {
    enqueue([this, done, frameText](Execution* e) {
      if (!e) return done(false, "the run has ended");
      std::unique_lock<std::mutex> lock(mutex_);
      if (!paused_) return done(false, "not paused (frame " + frameText(e) + ")");
      if (step_done_) return done(false, "a step is in progress");
      paused_ = false;
      lock.unlock();
      stream_.setState("running");
      done(true, "resumed at frame " + frameText(e));
    });
  } else if (service == "step") {
    const long long n = r.count;
    enqueue([this, done, n, frameText](Execution* e) {
      if (!e) return done(false, "the run has ended");
      std::unique_lock<std::mutex> lock(mutex_);
      if (!paused_) return done(false, "the run is not paused: pause it, then step");
      if (step_done_) return done(false, "a step is in progress");
      budget_ = n;
      step_done_ = done;
      lock.unlock();
      stream_.setState("running");
    });
  } else if (service == "save_session") {
    const std::string rel = relativeUnder(r.path.empty() ? "session" : r.path);
    if (rel.empty())
      return done(false, "'path' must be a folder under the output folder (no '..', not absolute)");
    const std::string dir = (boost::filesystem::path(out_dir_) / rel).string();
    enqueue([this, done, dir](Execution*) {
      try {
        done(true, save_session_(dir));
      } catch (const std::exception& e) {
        done(false, e.what());
      }
    });
  } else {
    // "do" names its action in the request; a module action is the service's own name.
    const std::string action = service == "do" ? r.action : service;
    bool known = service == "do";
    for (const auto& s : services_) known = known || s.name == service;
    if (!known) return done(false, "no service '" + service + "'");
    auto args = r.args;
    enqueue([this, done, action, args](Execution*) {
      try {
        const std::string message = invokeAction(run_, action, args);
        done(true, message.empty() ? "done" : message);
      } catch (const std::exception& e) {
        done(false, e.what());
      }
    });
  }
}

void RunControl::frame(const Frame& frame, Pipeline& pipeline, uint64_t frames, int64_t total) {
  stream_.frame(frame, pipeline, frames, total);
}

void RunControl::betweenFrames(Execution& execution) {
  std::unique_lock<std::mutex> lock(mutex_);
  frames_ = execution.frames();
  for (;;) {
    runQueued(lock, &execution);
    if (!paused_) return;
    if (budget_ > 0) {
      --budget_;
      return;
    }
    if (step_done_) {
      auto done = std::move(step_done_);
      step_done_ = nullptr;
      lock.unlock();
      stream_.setState("paused");
      done(true, "paused at frame " + std::to_string(execution.frames()));
      lock.lock();
      continue;
    }
    if (interrupted_ && interrupted_()) return;  // Ctrl-C ends a pause too
    cv_.wait_for(lock, std::chrono::milliseconds(100));
  }
}

void RunControl::finished(const RunResult& result, Pipeline& pipeline) {
  stream_.finished(result, pipeline);
  std::deque<Command> left;
  CallDone step;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ended_ = true;
    paused_ = false;
    left.swap(queue_);
    step = std::move(step_done_);
    step_done_ = nullptr;
  }
  if (step) step(false, "the run ended at frame " + std::to_string(frames_));
  std::lock_guard<std::mutex> one(after_end_mutex_);
  for (auto& c : left) c(nullptr);
}

}  // namespace plugslam::runtime
