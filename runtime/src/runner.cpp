#include "runner.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <boost/filesystem.hpp>
#include <chrono>
#include <cstdio>
#include <fstream>

#include "plugslam/errors.h"

namespace plugslam::runtime {

namespace fs = boost::filesystem;

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

std::string runReportJson(const RunReport& r) {
  std::string modules;
  for (const auto& m : r.modules) {
    modules += fmt::format("{}\n    \"{}\": {{\"total_s\": {:.6f}, \"calls\": {}, \"mean_ms\": {:.4f}}}",
                           modules.empty() ? "" : ",", m.module, m.total_s, m.calls,
                           m.calls ? 1e3 * m.total_s / m.calls : 0.0);
  }
  return fmt::format(
      "{{\n  \"frames\": {},\n  \"wall_time_s\": {:.6f},\n  \"hz\": {:.3f},\n  \"stopped_by\": "
      "\"{}\",\n  \"modules\": {{{}\n  }}\n}}\n",
      r.frames, r.wall_s, r.hz, r.stopped_by, modules);
}

RunReport runPipeline(RunConfig& run, const RunOptions& options) {
  boost::system::error_code ec;
  fs::create_directories(options.out_dir, ec);
  if (ec) throw InputError("cannot create output folder '" + options.out_dir + "': " + ec.message());
  Source& source = *run.source;
  Pipeline& pipeline = *run.pipeline;
  pipeline.timings().clear();
  for (auto& sink : run.outputs) sink->begin(options.out_dir);

  RunReport report;
  report.stopped_by = "end of data";
  const int64_t total = source.sizeHint();
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  Timings io_timings;
  for (uint64_t seq = 0;; ++seq) {
    if (run.max_frames() > 0 && seq >= static_cast<uint64_t>(run.max_frames())) {
      report.stopped_by = "max_frames";
      break;
    }
    Frame frame;
    frame.seq = seq;
    bool more;
    {
      ScopedTimer t(io_timings, source.name());
      try {
        more = source.next(frame);
      } catch (const InputError&) {
        throw;
      } catch (const std::exception& e) {
        throw ModuleError(source.name(), source.typeName(), e.what());
      }
    }
    if (!more) break;
    frame.seq = seq;
    pipeline.process(frame);
    for (auto& sink : run.outputs) {
      ScopedTimer t(io_timings, sink->name());
      sink->consume(frame);
    }
    report.frames = seq + 1;
    if (options.progress) options.progress(report.frames, total, elapsed());
  }
  RunResult result = pipeline.result();
  for (auto& sink : run.outputs) sink->end(result);
  report.wall_s = elapsed();
  report.hz = report.wall_s > 0 ? report.frames / report.wall_s : 0;
  report.modules = io_timings.entries();
  for (const auto& e : pipeline.timings().entries()) report.modules.push_back(e);
  writeTextFileAtomic((fs::path(options.out_dir) / "run.json").string(), runReportJson(report));
  return report;
}

}  // namespace plugslam::runtime
