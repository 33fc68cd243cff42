// plugslam optimize: read a pose-graph file (g2o or TORO), initialise, optimise with GN or LM,
// write the result as g2o and a JSON summary. A thin shell around optimizeGraphFile().
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>

#include "cli.h"
#include "commands/commands.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/solver/optimize_graph_file.h"

namespace plugslam::runtime {

namespace {

struct OptimizeArgs {
  std::string input, output, summary, solver = "gn", init = "chordal", robust,
                                      factorization = "auto";
  int iterations = 100;
  double robust_scale = 1.0;
  bool project_information = false, se_sync_weights = false;
};

Factorization parseFactorization(const std::string& name) {
  if (name == "auto") return Factorization::kAuto;
  if (name == "supernodal") return Factorization::kSupernodal;
  if (name == "simplicial") return Factorization::kSimplicial;
  if (name == "block") return Factorization::kBlock;
  throw InputError("unknown factorisation '" + name +
                   "'; expected auto, supernodal, simplicial or block");
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        else
          out += c;
    }
  }
  return out + "\"";
}

// The SDK's summary object extended with what the command was asked to do, the total time and
// the per-iteration statistics of the run that was kept.
std::string summaryJson(const OptimizeArgs& a, const OptimizeReport& r, double time_total) {
  std::string base = toJson(r);
  while (!base.empty() && base.back() != '}') base.pop_back();
  if (!base.empty()) base.pop_back();
  std::string s = base;
  s += fmt::format(
      ", \"input\": {}, \"output\": {}, \"format\": {}, \"solver\": {}, \"init\": {}, "
      "\"factorization\": {}, \"robust_kernel\": {}, \"robust_scale\": {:.17g}, "
      "\"project_information\": {}, "
      "\"projected_information\": {}, \"se_sync_weights\": {}, \"ok\": {}, "
      "\"time_total\": {:.6f}, \"time_setup\": {:.6f}, \"system_size\": {}, "
      "\"singular_systems\": {}, \"per_iteration\": [",
      jsonString(a.input), jsonString(a.output), jsonString(r.file.format), jsonString(a.solver),
      jsonString(a.init), jsonString(a.factorization), jsonString(a.robust), a.robust_scale,
      a.project_information, r.file.projected_information, a.se_sync_weights, r.result.ok(),
      time_total, r.result.time_setup, r.result.system_size, r.result.singular_systems);
  for (size_t i = 0; i < r.result.stats.size(); ++i) {
    const IterationStats& st = r.result.stats[i];
    s += fmt::format(
        "{}{{\"iteration\": {}, \"chi2\": {:.17g}, \"step_norm\": {:.6g}, \"lambda\": {:.6g}, "
        "\"accepted\": {}, \"time_linearize\": {:.6f}, \"time_solve\": {:.6f}, "
        "\"time_update\": {:.6f}}}",
        i ? ", " : "", st.iteration, st.chi2, st.step_norm, st.lambda, st.accepted,
        st.time_linearize, st.time_solve, st.time_update);
  }
  return s + "]}\n";
}

// One table row per iteration; with --init best a new table starts for each of the two runs.
class IterationTable {
 public:
  IterationTable(bool enabled, bool best_of) : enabled_(enabled), best_of_(best_of) {}
  void operator()(const IterationStats& st) {
    if (!enabled_) return;
    if (st.iteration == 0) {
      ++run_;
      if (best_of_)
        fmt::print("start {}: {}\n", run_,
                   run_ == 1 ? "file (odometry if no vertices)" : "chordal");
      fmt::print("{:>5} {:>16} {:>16} {:>10} {:>10} {:>11} {:>11} {:>11}\n", "iter", "chi2",
                 "chi2 before", "step", "lambda", "linearize", "solve", "update");
    }
    fmt::print(
        "{:>5} {:>16.10g} {:>16.10g} {:>10.3g} {:>10.3g} {:>9.3f}ms {:>9.3f}ms {:>9.3f}ms{}\n",
        st.iteration, st.chi2, st.chi2_before, st.step_norm, st.lambda, 1e3 * st.time_linearize,
        1e3 * st.time_solve, 1e3 * st.time_update, st.accepted ? "" : "  (rejected)");
    std::fflush(stdout);
  }

 private:
  bool enabled_, best_of_;
  int run_ = 0;
};

}  // namespace

void addOptimizeCommand(CLI::App& root, int& exit_code) {
  static OptimizeArgs a;
  auto* cmd = root.add_subcommand(
      "optimize", "Optimise a pose graph (g2o, TORO) and write it as g2o, with a summary");
  cmd->footer(
      "Reads g2o (VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, EDGE_SE3:QUAT, FIX) and TORO / HOG-Man\n"
      "(VERTEX2, EDGE2, VERTEX3, EDGE3); a file with edges only is initialised (--init). EDGE2\n"
      "information is read in TORO's order (xx xy yy tt xt yt), or in g2o's (xx xy xt yy yt tt)\n"
      "when only that order is positive definite for every edge (with a warning).");
  cmd->add_option("IN", a.input, "input pose graph (g2o or TORO)")->required();
  cmd->add_option("-o,--output", a.output,
                  "optimised graph to write (g2o); the summary goes to OUT.json unless --summary");
  cmd->add_option("--solver", a.solver, "gn (Gauss-Newton) or lm (Levenberg-Marquardt)")
      ->check(CLI::IsMember({"gn", "lm"}))
      ->capture_default_str();
  cmd->add_option("--iterations", a.iterations, "iteration budget")->capture_default_str();
  cmd->add_option("--init", a.init,
                  "starting point: file (the file's poses), odometry (spanning tree), chordal "
                  "(chordal relaxation), best (file and chordal, keep the lower chi2)")
      ->check(CLI::IsMember({"file", "odometry", "chordal", "best"}))
      ->capture_default_str();
  cmd->add_option("--robust", a.robust,
                  "robust kernel: Huber, Cauchy, Tukey or DCS (default: none)");
  cmd->add_option("--robust-scale", a.robust_scale, "robust kernel scale")->capture_default_str();
  cmd->add_flag("--project-information", a.project_information,
                "project information matrices that are not positive definite to the nearest "
                "positive definite ones (otherwise such a graph is refused)");
  cmd->add_flag("--se-sync-weights", a.se_sync_weights,
                "minimise SE-Sync's objective (isotropic weights from each information matrix)");
  cmd->add_option("--factorization", a.factorization,
                  "sparse factorisation: auto (block when all variables have one size), "
                  "supernodal or simplicial (CHOLMOD), block (plugslam's block Cholesky)")
      ->check(CLI::IsMember({"auto", "supernodal", "simplicial", "block"}))
      ->capture_default_str();
  cmd->add_option("--summary", a.summary, "JSON summary file (default: OUT.json)");
  cmd->callback([&exit_code] {
    const auto t_start = std::chrono::steady_clock::now();
    OptimizeOptions o;
    o.input = a.input;
    o.output = a.output;
    o.algorithm = parseAlgorithm(a.solver);
    o.init = parseInitMethod(a.init);
    if (a.iterations < 0)
      throw InputError("--iterations must be >= 0, got " + std::to_string(a.iterations));
    o.max_iterations = a.iterations;
    o.robust_kernel = a.robust;
    o.robust_scale = a.robust_scale;
    o.project_information = a.project_information;
    o.se_sync_weights = a.se_sync_weights;
    o.factorization = parseFactorization(a.factorization);
    // -q (global) lowers the log level to errors; the table is progress output, so it goes too.
    const bool table = spdlog::default_logger()->level() < spdlog::level::err;
    IterationTable printer(table, o.init == InitMethod::kBest);
    o.on_iteration = [&printer](const IterationStats& st) { printer(st); };

    OptimizeReport r;
    try {
      r = optimizeGraphFile(o);
    } catch (const ParseError&) {
      throw;
    } catch (const InputError& e) {
      const std::string what = e.what();
      if (!a.project_information && what.find("not positive definite") != std::string::npos)
        throw InputError(what + " (--project-information)");
      throw;
    }
    const double time_total =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();

    if (r.file.projected_information > 0)
      spdlog::warn("{}: projected {} of {} information matrices to the nearest positive definite",
                   a.input, r.file.projected_information, r.file.edges);
    if (r.file.skipped_records > 0)
      spdlog::warn("{}: skipped {} records of types other than poses and pose edges", a.input,
                   r.file.skipped_records);
    if (table) {
      fmt::print(
          "{}: {} poses, {} edges ({}D {}{})\n"
          "chi2 {:.10g} -> {:.10g} in {} iterations ({}); SE-Sync objective {:.10g}\n"
          "time: read {:.3f} s, init {:.3f} s, optimize {:.3f} s, write {:.3f} s, total {:.3f} s\n",
          a.input, r.poses, r.edges, r.file.dimension, r.file.format,
          r.file.has_vertices ? "" : ", edges only", r.initial_chi2, r.final_chi2, r.iterations,
          toString(r.reason), r.se_sync_objective, r.time_read, r.time_init, r.time_optimize,
          r.time_write, time_total);
    }

    std::string summary = a.summary;
    if (summary.empty() && !a.output.empty()) summary = a.output + ".json";
    if (!summary.empty()) {
      try {
        writeFileAtomically(summary, summaryJson(a, r, time_total));
      } catch (const InputError& e) {
        // An unwritable summary path is a bad argument, like an unwritable -o.
        throw InputError(std::string("--summary: ") + e.what());
      }
    }
    if (table && !a.output.empty()) fmt::print("wrote {}\n", a.output);
    if (table && !summary.empty()) fmt::print("wrote {}\n", summary);
    std::fflush(stdout);

    if (r.reason == StopReason::kSolverFailure || r.reason == StopReason::kNoProgress) {
      throw Error(fmt::format("{}: the {} solver failed ({}){}", a.input, a.solver,
                              toString(r.reason),
                              a.output.empty() ? "" : "; the last good estimate was written"));
    }
    exit_code = kOk;
  });
}

}  // namespace plugslam::runtime
