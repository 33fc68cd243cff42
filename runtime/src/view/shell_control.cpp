#include "view/shell_control.h"

#include <spdlog/spdlog.h>
#include <yaml-cpp/yaml.h>

#include <boost/filesystem.hpp>

#include "editor/config_editor.h"
#include "plugslam/errors.h"
#include "shell/module_paths.h"
#include "view/parameters.h"

namespace plugslam::runtime {

namespace {

// Requests waiting for the shell at most; a client sending more only fills a queue.
constexpr size_t kMaxPending = 64;

}  // namespace

ShellControl::ShellControl(ViewHub& hub, std::string out_dir)
    : hub_(hub),
      out_dir_(std::move(out_dir)),
      // The requests answered while stopping: none is left without a reply.
      jobs_(kMaxPending, "viewer request failed", JobThread::OnStop::kRunWaiting) {}

ShellControl::~ShellControl() { shutdown(); }

void ShellControl::attach(Shell& shell) { shell_ = &shell; }

void ShellControl::shutdown() { jobs_.stop(); }

void ShellControl::enqueue(std::function<void()> job, std::function<void()> refuse) {
  if (!shell_ || jobs_.post(std::move(job)) != JobThread::Posted::kQueued) refuse();
}

void ShellControl::stateChanged(const std::string& state) {
  // Called by the shell between frames: the worker is not inside frame().
  if (stream_) stream_->setState(state);
}

std::vector<foxglove::Service> ShellControl::services() {
  if (!shell_) return standardServices(nullptr);
  std::lock_guard<std::recursive_mutex> lock(shell_->command_mutex_);
  return standardServices(shell_->run_.get());
}

void ShellControl::getParameters(std::vector<std::string> names, ParametersDone done) {
  enqueue(
      [this, names, done] {
        std::lock_guard<std::recursive_mutex> lock(shell_->command_mutex_);
        if (!shell_->run_) return done({}, {"no config loaded (load CONFIG)"});
        std::vector<std::string> errors;
        auto frames = shell_->lockBetweenFrames();
        auto values = listParameters(*shell_->run_, names, errors);
        frames.unlock();
        done(std::move(values), std::move(errors));
      },
      [done] { done({}, {"the shell is busy or stopping"}); });
}

void ShellControl::setParameters(std::vector<foxglove::ParameterAssignment> assignments,
                                 ParametersDone done) {
  enqueue(
      [this, assignments, done] {
        std::lock_guard<std::recursive_mutex> lock(shell_->command_mutex_);
        std::vector<std::string> errors, names;
        for (const auto& a : assignments) names.push_back(a.name);
        if (!shell_->doc_) return done({}, {"no config loaded (load CONFIG)"});
        if (!shell_->active()) {
          // No run in progress: exactly the shell's `set` (validated, committed, rebuilt).
          for (const auto& a : assignments) {
            bool ok = false;
            const std::string out = shell_->capture("set " + a.name + "=" + a.value, ok);
            if (!ok) errors.push_back(out.rfind("error: ", 0) == 0 ? out.substr(7) : out);
          }
        } else {
          std::vector<foxglove::ParameterAssignment> live;
          for (const auto& a : assignments) {
            try {
              const std::string why = liveRefusal(*shell_->run_, a.name);
              if (why.empty()) live.push_back(a);
              else errors.push_back("'" + a.name + "' cannot change during a run: " + why);
            } catch (const std::exception& e) {
              errors.push_back(e.what());
            }
          }
          if (!live.empty()) {
            ConfigDocument copy = *shell_->doc_;
            copy.root.reset(YAML::Clone(shell_->doc_->root));
            bool valid = true;
            try {
              for (const auto& a : live) applyOverride(copy, a.name + "=" + a.value);
              shell_->build(copy);  // exactly what `set` validates with
            } catch (const std::exception& e) {
              errors.push_back(e.what());
              valid = false;
            }
            if (valid) {
              auto frames = shell_->lockBetweenFrames();
              for (const auto& a : live) {
                try {
                  applyLive(*shell_->run_, a.name, a.value);
                  applyOverride(*shell_->doc_, a.name + "=" + a.value);
                  spdlog::info("viewer: {} = {}", a.name, a.value);
                } catch (const std::exception& e) {
                  errors.push_back(e.what());
                }
              }
            }
          }
        }
        std::vector<foxglove::Parameter> values;
        if (shell_->run_) {
          auto frames = shell_->lockBetweenFrames();
          values = listParameters(*shell_->run_, names, errors);
        }
        done(std::move(values), std::move(errors));
      },
      [done] { done({}, {"the shell is busy or stopping"}); });
}

void ShellControl::call(const std::string& service, const std::string& request, CallDone done) {
  if (editor::ConfigEditor::handles(service)) {
    enqueue(
        [this, service, request, done] {
          std::string yaml, name;
          {
            std::lock_guard<std::recursive_mutex> lock(shell_->command_mutex_);
            if (!shell_->doc_) return done(false, "no config loaded (load CONFIG)");
            yaml = resolvedYaml(*shell_->doc_);
            name = shell_->doc_->file;
          }
          try {
            done(true, editor::ConfigEditor(editor::editorRoot(), yaml, name).call(service, request));
          } catch (const std::exception& e) {
            done(false, e.what());
          }
        },
        [done] { done(false, "the shell is busy or stopping"); });
    return;
  }
  ServiceRequest r;
  if (!parseServiceRequest(request, r, done)) return;
  std::string line;
  if (service == "pause" || service == "resume") {
    line = service;
  } else if (service == "step") {
    line = "step " + std::to_string(r.count);
  } else if (service == "save_session") {
    namespace fs = boost::filesystem;
    const fs::path p(r.path.empty() ? "session" : r.path);
    bool ok = !p.is_absolute() && p.string().find_first_of(" \t\"'") == std::string::npos;
    for (const auto& part : p) ok = ok && part != "..";
    if (!ok)
      return done(false, "'path' must be a folder under the output folder (no '..', not "
                         "absolute, no spaces or quotes)");
    line = "save " + (fs::path(out_dir_) / p).lexically_normal().string();
  }
  if (!line.empty()) {
    return enqueue(
        [this, line, done] {
          bool ok = false;
          std::string out = shell_->capture(line, ok);
          if (!ok && out.rfind("error: ", 0) == 0) out = out.substr(7);
          done(ok, out);
        },
        [done] { done(false, "the shell is busy or stopping"); });
  }
  const std::string action = service == "do" ? r.action : service;
  auto args = r.args;
  enqueue(
      [this, action, args, done] {
        std::lock_guard<std::recursive_mutex> lock(shell_->command_mutex_);
        if (!shell_->run_) return done(false, "no config loaded (load CONFIG)");
        try {
          auto frames = shell_->lockBetweenFrames();
          const std::string message = invokeAction(*shell_->run_, action, args);
          frames.unlock();
          done(true, message.empty() ? "done" : message);
        } catch (const std::exception& e) {
          done(false, e.what());
        }
      },
      [done] { done(false, "the shell is busy or stopping"); });
}

void ShellControl::frame(const Frame& frame, Pipeline& pipeline, uint64_t frames, int64_t total) {
  if (frames == 1 || !stream_) {
    // A new run: its maps start again from 0, so what was latched belongs to the last one.
    hub_.clearLatched();
    stream_ = std::make_unique<ViewStream>(++runs_);
  }
  stream_->frame(frame, pipeline, frames, total);
}

void ShellControl::finished(const RunResult& result, Pipeline& pipeline) {
  if (stream_) stream_->finished(result, pipeline);
}

}  // namespace plugslam::runtime
