#include "runner.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <boost/filesystem.hpp>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/eval/ate.h"
#include "plugslam/eval/rpe.h"
#include "plugslam/trajectory.h"

namespace plugslam::runtime {

namespace fs = boost::filesystem;

RunObserver::~RunObserver() = default;

namespace {
// A figure with the decimals run.json has always printed it with (the timers resolve
// microseconds, rates a thousandth), so its value is the same as before the JSON library wrote
// it; a NaN or infinity stays as it is and is written as null.
double decimals(double v, int places) {
  if (!std::isfinite(v)) return v;
  const std::string text = fmt::format("{:.{}f}", v, places);
  double out = v;
  std::from_chars(text.data(), text.data() + text.size(), out);  // locale-independent
  return out;
}

// A measured figure, or null when there is none.
nlohmann::ordered_json optionalFigure(const std::optional<double>& v) {
  if (!v || !std::isfinite(*v)) return nullptr;
  return decimals(*v, 6);
}

// The tracker's counters under run.json's tracking_ keys (failures and local maps are written
// with the rest of the report).
void writeTrackerStats(nlohmann::ordered_json& j, const TrackerStats& s) {
  j["tracking_searched"] = s.searched;
  j["tracking_ambiguous"] = s.ambiguous;
  j["tracking_hypotheses"] = s.hypotheses;
  j["tracking_unchecked"] = s.unchecked;
  j["tracking_unchecked_frames"] = s.unchecked_frames;
  j["tracking_time_s"] = {{"search", s.search_s}, {"refine", s.refine_s}, {"merge", s.merge_s}};
}
}  // namespace

std::string runReportJson(const RunReport& r) {
  // Keys in the order readers have always seen them.
  nlohmann::ordered_json j;
  j["frames"] = r.frames;
  j["wall_time_s"] = decimals(r.wall_s, 6);
  j["hz"] = decimals(r.hz, 3);
  j["pipeline_time_s"] = decimals(r.pipeline_s, 6);
  j["pipeline_hz"] = decimals(r.pipeline_hz, 3);
  j["stopped_by"] = r.stopped_by;
  j["error"] = r.error.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(r.error);
  j["tracked_frames"] = r.tracked;
  j["local_maps"] = r.local_maps;
  j["tracking_failures"] = r.tracking_failures;
  nlohmann::ordered_json reasons = nlohmann::ordered_json::object();
  for (const auto& [reason, n] : r.tracking_failure_reasons) reasons[reason] = n;
  j["tracking_failure_reasons"] = reasons;
  writeTrackerStats(j, r.tracking);
  j["module_errors"] = r.module_errors;
  j["reference"] = {{"ate_rmse_m", optionalFigure(r.ate_rmse)},
                    {"ate_max_m", optionalFigure(r.ate_max)},
                    {"rpe_1m_rmse_m", optionalFigure(r.rpe_rmse)}};
  const GraphStats& g = r.graph;
  j["graph"] = {{"nodes", g.nodes},
                {"edges", g.edges},
                {"loop_candidates", g.candidates},
                {"loops_accepted", g.loops_accepted},
                {"loops_rejected", g.loops_rejected},
                {"loops_restored", g.loops_restored},
                {"optimizations", g.optimizations},
                {"optimization_time_s", decimals(g.optimization_time, 6)},
                {"loop_detection_time_s", decimals(g.detection_time, 6)},
                {"loop_validation_time_s", decimals(g.validation_time, 6)},
                {"final_chi2", decimals(g.final_chi2, 6)}};
  nlohmann::ordered_json components = nlohmann::ordered_json::array();
  for (const auto& [first, maps] : r.graph_components)
    components.push_back({{"first_map", first}, {"maps", maps}});
  j["graph"]["components"] = components;
  j["locked_on_after_frames"] = r.locked_on_after;
  nlohmann::ordered_json& modules = j["modules"] = nlohmann::ordered_json::object();
  for (const auto& m : r.modules) {
    modules[m.module] = {{"total_s", decimals(m.total_s, 6)},
                         {"calls", m.calls},
                         {"mean_ms", decimals(m.calls ? 1e3 * m.total_s / m.calls : 0.0, 4)}};
  }
  nlohmann::ordered_json& statistics = j["statistics"] = nlohmann::ordered_json::object();
  for (const auto& [module, figures] : r.statistics) {
    nlohmann::ordered_json& fields = statistics[module] = nlohmann::ordered_json::object();
    for (const auto& f : figures) fields[f.name] = optionalFigure(f.value);
  }
  // An error message may quote a file's bytes: invalid UTF-8 is replaced, never a throw.
  return j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

std::string scoreLine(const RunReport& r, const std::string& reference) {
  if (!r.ate_rmse) return "";
  std::string line = fmt::format("against '{}': ATE rmse {:.4f} m (max {:.4f} m), ", reference,
                                 *r.ate_rmse, r.ate_max.value_or(NAN));
  if (r.rpe_rmse) return line + fmt::format("RPE(1 m) rmse {:.4f} m\n", *r.rpe_rmse);
  return line + "no RPE(1 m): " + r.rpe_unavailable + "\n";
}

std::string loopsClosedText(const GraphStats& g) {
  std::string text = fmt::format("{} loops closed", g.loops_accepted);
  if (g.loops_restored > 0)
    text += fmt::format(" ({} more restored with the session)", g.loops_restored);
  return text;
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
    report.rpe_unavailable =
        fmt::format("the run is too short for it (the reference path is {:.2f} m)", path);
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
  if (run_.max_frames() > 0 && (total_ < 0 || total_ > run_.max_frames()))
    total_ = run_.max_frames();
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
  std::unique_ptr<Frame> frame;
  if (run_.read_ahead() > 0) {
    if (!reader_)
      reader_ = std::make_unique<ReadAhead>(
          [&source](Frame& f) { return asModule(source, [&] { return source.next(f); }); },
          static_cast<size_t>(run_.read_ahead()));
    ReadFrame read = reader_->next();
    if (read.seconds > 0) io_timings_.add(source.name(), read.seconds);
    if (read.error) std::rethrow_exception(read.error);
    frame = std::move(read.frame);
  } else {
    frame = std::make_unique<Frame>();
    frame->seq = seq;
    ScopedTimer t(io_timings_, source.name());
    if (!asModule(source, [&] { return source.next(*frame); })) frame.reset();
  }
  if (!frame) {
    exhausted_ = true;
    return false;
  }
  frame->seq = seq;
  due_ = clock_.due(frame->stamp, PlaybackClock::Clock::now());
  if (seq == 0) first_stamp_ = frame->stamp;
  constexpr uint64_t kStampCheck = 10;  // frames after which a paced run expects time to pass
  if (clock_.rate() > 0 && seq == kStampCheck && frame->stamp == first_stamp_)
    spdlog::warn(
        "--rate {}: the source's frames carry no timestamps (frame {} is stamped like "
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
  if (processed && frame.estimate.valid && frame.estimate.frozen) ++frozen_frames_;
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
  reader_.reset();  // nothing more is read
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
  report.locked_on_after = pipeline.lockedOnAfter();
  if (report.locked_on_after < 0)
    spdlog::warn("localization never locked on: place recognition found no place of the "
                 "session in {} frames (another place, or too little seen of it)",
                 report.frames);
  else if (report.locked_on_after > 0)
    spdlog::info("localization locked on after {} frames (lost before that)",
                 report.locked_on_after);
  if (pipeline.graph) {
    report.graph = pipeline.graph->stats();
    const std::vector<int64_t> components =
        graphComponents(result.local_maps.size(), result.edges);
    for (size_t i = 0; i < components.size(); ++i) {
      if (components[i] == static_cast<int64_t>(i))
        report.graph_components.emplace_back(static_cast<int64_t>(i), 0);
      for (auto& [first, maps] : report.graph_components)
        if (first == components[i]) ++maps;
    }
    // Maps no loop joined to map 0's have no common frame with them: their poses in the outputs
    // are where a weak prior left them, not measured.
    for (size_t c = 1; c < report.graph_components.size(); ++c)
      spdlog::warn("graph component of maps {}.. ({} maps) is not joined to map 0's: no loop "
                   "links them (a session's start unknown and no shared place recognized, or a "
                   "tracker reset); its poses are not in map 0's frame",
                   report.graph_components[c].first, report.graph_components[c].second);
  }
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
    const TrackerStats& stats = pipeline.tracker->stats();
    report.tracking = stats;
    report.local_maps = stats.local_maps;
    report.tracking_failures = stats.failed;
    for (std::size_t i = 1; i < kAlignFailures; ++i)
      report.tracking_failure_reasons.emplace_back(toString(static_cast<AlignFailure>(i)),
                                                   stats.failures[i]);
  }
  // Past 5 % the map is mostly stitched from predictions and weak edges: say so, with why.
  if (frozen_frames_ == 0 && report.frames > 0 && 20 * report.tracking_failures > report.frames) {
    std::string why;
    for (const auto& [reason, n] : report.tracking_failure_reasons)
      if (n) why += (why.empty() ? "" : ", ") + reason + " " + std::to_string(n);
    spdlog::warn(
        "tracking failed on {} of {} frames ({:.1f} %): {}; each failure starts a new "
        "local map joined by a weak edge (the debug log, -v, names every frame's reason)",
        report.tracking_failures, report.frames, 100.0 * report.tracking_failures / report.frames,
        why);
  }
  if (report.tracking.unchecked > 0)
    spdlog::warn(
        "{} of {} frames have poses their cues could not check (run.json "
        "tracking_unchecked_frames lists them): they may be wrong",
        report.tracking.unchecked, report.frames);
  // In localization a failed frame is one no saved map explains: when that is most of them the
  // poses are mostly predictions, and the session is probably of another place (or sensor).
  if (frozen_frames_ > 0 && 2 * report.tracking_failures > frozen_frames_)
    spdlog::warn(
        "localization: {} of {} frames did not align with any saved map; the session "
        "is probably of another place, or the sensors or config differ from its run",
        report.tracking_failures, frozen_frames_);
  scoreAgainstGroundTruth(result, pipeline.tracker ? pipeline.tracker->dimension() : 3, report);
  if (!result.reference.empty())
    writeTumTrajectory(result.reference, (fs::path(options_.out_dir) / "reference.tum").string());
  if (options_.observer) options_.observer->finished(result, pipeline);
  for (const auto& e : pipeline.timings().entries()) report.pipeline_s += e.total_s;
  report.pipeline_hz = report.pipeline_s > 0 ? report.frames / report.pipeline_s : 0;
  report.wall_s = elapsed();
  report.hz = report.wall_s > 0 ? report.frames / report.wall_s : 0;
  report.modules = io_timings_.entries();
  for (const auto& e : pipeline.timings().entries()) report.modules.push_back(e);
  report.statistics = collectStatistics(pipeline);
  writeFileAtomically((fs::path(options_.out_dir) / "run.json").string(), runReportJson(report));
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
        if (options.wait_until) {
          options.wait_until(due);
          stop = interrupted();
        } else {
          for (auto now = PlaybackClock::Clock::now(); now < due && !stop;
               now = PlaybackClock::Clock::now()) {
            std::this_thread::sleep_until(std::min(due, now + std::chrono::milliseconds(50)));
            stop = interrupted();
          }
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
