#include "runner.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <boost/filesystem.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <thread>

#include "plugslam/errors.h"
#include "plugslam/eval/ate.h"
#include "plugslam/eval/rpe.h"
#include "plugslam/trajectory.h"

namespace plugslam::runtime {

namespace fs = boost::filesystem;

RunObserver::~RunObserver() = default;

void writeTextFileAtomic(const std::string& path, const std::string& content) {
  fs::path target(path);
  fs::path tmp = target.parent_path() / (target.filename().string() + ".tmp-" +
                                         std::to_string(::getpid()));
  {
    std::ofstream out(tmp.string(), std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot write '" + tmp.string() + "'");
    out << content;
    out.flush();
    if (!out) throw Error("write to '" + tmp.string() + "' failed (disk full?)");
  }
  boost::system::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw Error("cannot move '" + tmp.string() + "' to '" + path + "'");
  }
}

namespace {
std::string jsonNumber(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? fmt::format("{:.6f}", *v) : "null";
}

// A JSON string literal: error messages quote file contents and names.
std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (u < 0x20) {
      out += fmt::format("\\u{:04x}", u);
    } else {
      out += c;
    }
  }
  return out + "\"";
}
}  // namespace

std::string runReportJson(const RunReport& r) {
  std::string modules;
  for (const auto& m : r.modules) {
    modules += fmt::format("{}\n    \"{}\": {{\"total_s\": {:.6f}, \"calls\": {}, \"mean_ms\": {:.4f}}}",
                           modules.empty() ? "" : ",", m.module, m.total_s, m.calls,
                           m.calls ? 1e3 * m.total_s / m.calls : 0.0);
  }
  std::string statistics;
  for (const auto& [module, figures] : r.statistics) {
    std::string fields;
    for (const auto& f : figures)
      fields += fmt::format("{}{}: {}", fields.empty() ? "" : ", ", jsonString(f.name),
                            jsonNumber(f.value));
    statistics += fmt::format("{}\n    {}: {{{}}}", statistics.empty() ? "" : ",",
                              jsonString(module), fields);
  }
  return fmt::format(
      "{{\n  \"frames\": {},\n  \"wall_time_s\": {:.6f},\n  \"hz\": {:.3f},\n  \"pipeline_time_s\": {:.6f},\n  \"pipeline_hz\": {:.3f},\n  \"stopped_by\": "
      "\"{}\",\n  \"error\": {},\n  \"tracked_frames\": {},\n  \"local_maps\": {},\n  \"tracking_failures\": {},\n"
      "  \"module_errors\": {},\n"
      "  \"reference\": {{\"ate_rmse_m\": {}, \"ate_max_m\": {}, \"rpe_1m_rmse_m\": {}}},\n"
      "  \"graph\": {{\"nodes\": {}, \"edges\": {}, \"loop_candidates\": {}, \"loops_accepted\": {}, "
      "\"loops_rejected\": {}, \"optimizations\": {}, \"optimization_time_s\": {:.6f}, "
      "\"loop_detection_time_s\": {:.6f}, \"loop_validation_time_s\": {:.6f}, "
      "\"final_chi2\": {:.6f}}},\n"
      "  \"modules\": {{{}\n  }},\n  \"statistics\": {{{}\n  }}\n}}\n",
      r.frames, r.wall_s, r.hz, r.pipeline_s, r.pipeline_hz, r.stopped_by, r.error.empty() ? "null" : jsonString(r.error), r.tracked,
      r.local_maps, r.tracking_failures, r.module_errors,
      jsonNumber(r.ate_rmse), jsonNumber(r.ate_max), jsonNumber(r.rpe_rmse), r.graph.nodes,
      r.graph.edges, r.graph.candidates, r.graph.loops_accepted, r.graph.loops_rejected,
      r.graph.optimizations, r.graph.optimization_time, r.graph.detection_time,
      r.graph.validation_time, r.graph.final_chi2, modules, statistics);
}

std::string scoreLine(const RunReport& r, const std::string& reference) {
  if (!r.ate_rmse) return "";
  std::string line = fmt::format("against '{}': ATE rmse {:.4f} m (max {:.4f} m), ", reference,
                                 *r.ate_rmse, r.ate_max.value_or(NAN));
  if (r.rpe_rmse) return line + fmt::format("RPE(1 m) rmse {:.4f} m\n", *r.rpe_rmse);
  return line + "no RPE(1 m): " + r.rpe_unavailable + "\n";
}

// Runs one call into a source or sink (plugin code) so that whatever it throws names the module:
// InputError passes (bad input, exit 2), anything else becomes a ModuleError (exit 1), including
// exceptions not derived from std::exception.
template <class F>
static auto asModule(const Configurable& m, F&& step) -> decltype(step()) {
  try {
    return step();
  } catch (const InputError&) {
    throw;
  } catch (const ModuleError&) {
    throw;
  } catch (const std::exception& e) {
    throw ModuleError(m.name(), m.typeName(), e.what());
  } catch (...) {
    throw ModuleError(m.name(), m.typeName(), "an exception not derived from std::exception");
  }
}

static void scoreAgainstGroundTruth(const RunResult& result, int dimension, RunReport& report) {
  if (result.reference.size() < 2 || result.trajectory.size() < 2) return;
  try {
    AteOptions ate;
    ate.alignment = dimension == 2 ? Alignment::SE2 : Alignment::SE3;
    AteResult a = computeAte(result.reference, result.trajectory, ate);
    report.ate_rmse = a.translation.rmse;
    report.ate_max = a.translation.max;
  } catch (const InputError& e) {
    spdlog::warn("cannot score against ground truth: {}", e.what());
    return;
  }
  RpeOptions rpe;
  rpe.unit = RpeUnit::Meters;
  rpe.delta = 1.0;
  double path = 0;
  for (size_t i = 1; i < result.reference.size(); ++i)
    path += (result.reference[i].pose.translation() - result.reference[i - 1].pose.translation())
                .norm();
  if (path < rpe.delta) {
    report.rpe_unavailable = fmt::format(
        "the run is too short for it (the reference path is {:.2f} m)", path);
    return;
  }
  try {
    report.rpe_rmse = computeRpe(result.reference, result.trajectory, rpe).translation.rmse;
  } catch (const InputError& e) {
    report.rpe_unavailable = e.what();
  }
}

Execution::Execution(RunConfig& run, RunOptions options)
    : run_(run), options_(std::move(options)), clock_(options_.rate) {
  boost::system::error_code ec;
  fs::create_directories(options_.out_dir, ec);
  if (ec)
    throw InputError("cannot create output folder '" + options_.out_dir + "': " + ec.message());
  run_.pipeline->timings().clear();
  for (auto& sink : run_.outputs) asModule(*sink, [&] { sink->begin(options_.out_dir); });
  report_.stopped_by = "end of data";
  total_ = run_.source->sizeHint();
  if (run_.max_frames() > 0 && (total_ < 0 || total_ > run_.max_frames())) total_ = run_.max_frames();
  start_ = std::chrono::steady_clock::now();
}

double Execution::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void Execution::setRate(double rate) {
  clock_.setRate(rate);
  if (pending_) due_ = clock_.due(pending_->stamp, PlaybackClock::Clock::now());
}

bool Execution::fetch() {
  if (pending_) return true;
  if (exhausted_ || finished_) return false;
  const uint64_t seq = report_.frames;
  if (run_.max_frames() > 0 && seq >= static_cast<uint64_t>(run_.max_frames())) {
    report_.stopped_by = "max_frames";
    exhausted_ = true;
    return false;
  }
  Source& source = *run_.source;
  auto frame = std::make_unique<Frame>();
  frame->seq = seq;
  bool more;
  {
    ScopedTimer t(io_timings_, source.name());
    more = asModule(source, [&] { return source.next(*frame); });
  }
  if (!more) {
    exhausted_ = true;
    return false;
  }
  frame->seq = seq;
  due_ = clock_.due(frame->stamp, PlaybackClock::Clock::now());
  if (seq == 0) first_stamp_ = frame->stamp;
  constexpr uint64_t kStampCheck = 10;  // frames after which a paced run expects time to pass
  if (clock_.rate() > 0 && seq == kStampCheck && frame->stamp == first_stamp_)
    spdlog::warn("--rate {}: the source's frames carry no timestamps (frame {} is stamped like "
                 "frame 0), so the run is not paced",
                 clock_.rate(), seq);
  pending_ = std::move(frame);
  return true;
}

PlaybackClock::Clock::time_point Execution::nextDue() {
  return fetch() ? due_ : PlaybackClock::Clock::now();
}

bool Execution::step() {
  if (!fetch()) return false;
  const std::unique_ptr<Frame> owned = std::move(pending_);
  Frame& frame = *owned;
  const uint64_t seq = frame.seq;
  const bool skip = run_.on_module_error() == "skip";
  bool processed = true;
  try {
    run_.pipeline->process(frame);
  } catch (const ModuleError& e) {
    if (!skip) throw;
    skipped(seq, e);
    processed = false;  // the sinks never see a frame the pipeline did not finish
  }
  for (auto& sink : run_.outputs) {
    if (!processed) break;
    ScopedTimer t(io_timings_, sink->name());
    try {
      asModule(*sink, [&] { sink->consume(frame); });
    } catch (const ModuleError& e) {
      if (!skip) throw;
      skipped(seq, e);
    }
  }
  report_.frames = seq + 1;
  if (options_.observer && processed) {
    ScopedTimer t(io_timings_, "viewer");
    options_.observer->frame(frame, *run_.pipeline, report_.frames, total_);
  }
  if (options_.progress) {
    uint64_t loops = run_.pipeline->graph ? run_.pipeline->graph->stats().loops_accepted : 0;
    options_.progress(report_.frames, total_, elapsed(), loops);
  }
  return true;
}

void Execution::skipped(uint64_t seq, const ModuleError& e) {
  constexpr uint64_t kMaxWarnings = 5;
  if (++report_.module_errors <= kMaxWarnings)
    spdlog::warn("frame {} skipped (on_module_error: skip): {}{}", seq, e.what(),
                 report_.module_errors == kMaxWarnings ? " (further ones are only counted)" : "");
}

RunReport Execution::finish(const std::string& stopped_by, const std::string& error) {
  if (finished_) throw InputError("this run has already finished");
  finished_ = true;
  RunReport report = report_;
  if (!stopped_by.empty()) report.stopped_by = stopped_by;
  report.error = error;
  if (report.module_errors > 0)
    spdlog::warn("{} frame(s) skipped because a module failed (on_module_error: skip)",
                 report.module_errors);
  Pipeline& pipeline = *run_.pipeline;
  // options_.finishing hears when the final work ends, however it ends.
  struct Finishing {
    const std::function<void(bool)>& tell;
    explicit Finishing(const std::function<void(bool)>& f) : tell(f) {
      if (tell) tell(false);
    }
    ~Finishing() {
      if (tell) tell(true);
    }
  } finishing(options_.finishing);
  pipeline.finish();
  RunResult result = pipeline.result();
  if (pipeline.graph) report.graph = pipeline.graph->stats();
  // Every sink gets its end() even when one fails, and run.json is written; the first failure
  // is rethrown after.
  std::exception_ptr sink_failure;
  for (auto& sink : run_.outputs) {
    try {
      asModule(*sink, [&] { sink->end(result); });
    } catch (const Error& e) {
      if (sink_failure) spdlog::error("{}", e.what());  // the first one is rethrown below
      if (!sink_failure) {
        sink_failure = std::current_exception();
        if (report.error.empty()) report.error = e.what();
        if (report.stopped_by != "error") report.stopped_by = "error";
      }
    }
  }
  report.tracked = result.trajectory.size();
  if (pipeline.tracker) {
    report.local_maps = pipeline.tracker->stats().local_maps;
    report.tracking_failures = pipeline.tracker->stats().failed;
  }
  scoreAgainstGroundTruth(result, pipeline.tracker ? pipeline.tracker->dimension() : 3, report);
  if (!result.reference.empty())
    writeTumTrajectory(result.reference,
                       (fs::path(options_.out_dir) / "reference.tum").string());
  if (options_.observer) options_.observer->finished(result, pipeline);
  for (const auto& e : pipeline.timings().entries()) report.pipeline_s += e.total_s;
  report.pipeline_hz = report.pipeline_s > 0 ? report.frames / report.pipeline_s : 0;
  report.wall_s = elapsed();
  report.hz = report.wall_s > 0 ? report.frames / report.wall_s : 0;
  report.modules = io_timings_.entries();
  for (const auto& e : pipeline.timings().entries()) report.modules.push_back(e);
  report.statistics = collectStatistics(pipeline);
  writeTextFileAtomic((fs::path(options_.out_dir) / "run.json").string(), runReportJson(report));
  if (sink_failure) std::rethrow_exception(sink_failure);
  return report;
}

RunReport runPipeline(RunConfig& run, const RunOptions& options) {
  Execution execution(run, options);
  std::string stopped_by;
  std::exception_ptr failure;
  std::string error;
  const auto interrupted = [&] { return options.interrupted && options.interrupted(); };
  for (;;) {
    if (options.observer) options.observer->betweenFrames(execution);
    bool stop = interrupted();
    try {
      // Paced (--rate): wait for the next frame's time, a Ctrl-C still ending the wait.
      if (!stop) {
        const auto due = execution.nextDue();
        for (auto now = PlaybackClock::Clock::now(); now < due && !stop;
             now = PlaybackClock::Clock::now()) {
          std::this_thread::sleep_until(std::min(due, now + std::chrono::milliseconds(50)));
          stop = interrupted();
        }
      }
      if (!stop && !execution.step()) break;
    } catch (const Error& e) {
      // Bad input or a failing module: what was built so far is still finished and written.
      failure = std::current_exception();
      error = e.what();
      break;
    }
    if (stop) {
      stopped_by = "interrupted";
      if (options.on_interrupt) options.on_interrupt();
      break;
    }
  }
  // Nothing was built before the first frame failed: nothing to write or save.
  if (failure && execution.frames() == 0) std::rethrow_exception(failure);
  if (failure)
    spdlog::info("run stopped by an error after {} frame(s); finishing it", execution.frames());
  try {
    RunReport report = execution.finish(failure ? "error" : stopped_by, error);
    if (!failure) return report;
  } catch (const Error&) {
    // A sink that could not write its output (reported already): the rest is still saved.
    if (!failure) failure = std::current_exception();
  }
  try {
    if (options.stopped_by_error) options.stopped_by_error();
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
  }
  std::rethrow_exception(failure);
}

}  // namespace plugslam::runtime
