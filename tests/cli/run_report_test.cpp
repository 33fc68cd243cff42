// run.json as readers (tests, scripts/bench) see it: valid JSON, its keys in their order, every
// figure with the decimals it has always had, and null where a figure is missing or not finite.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "runner.h"

namespace plugslam::runtime {
namespace {

using nlohmann::ordered_json;

RunReport sampleReport() {
  RunReport r;
  r.frames = 996;
  r.wall_s = 1.2643624;
  r.hz = 787.7494;
  r.pipeline_s = 0.7206501;
  r.pipeline_hz = 1382.0862;
  r.stopped_by = "end of data";
  r.tracked = 996;
  r.local_maps = 52;
  r.tracking_failures = 3;
  r.tracking_failure_reasons = {{"no_data", 0}, {"too_few_inliers", 2}, {"degenerate", 1}};
  r.modules = {{"source", 0.3387041, 997}, {"pipeline.tracker", 0.5451601, 996}};
  r.graph.nodes = 52;
  r.graph.loops_accepted = 64;
  r.graph.final_chi2 = 14.0602934;
  r.ate_rmse = 0.0013724;
  return r;
}

std::vector<std::string> keys(const ordered_json& j) {
  std::vector<std::string> out;
  for (const auto& [k, v] : j.items()) out.push_back(k);
  return out;
}

TEST(RunReportJson, KeysInOrderAndFiguresWithTheirDecimals) {
  const std::string text = runReportJson(sampleReport());
  const ordered_json j = ordered_json::parse(text);
  EXPECT_EQ(keys(j), (std::vector<std::string>{
                         "frames", "wall_time_s", "hz", "pipeline_time_s", "pipeline_hz",
                         "stopped_by", "error", "tracked_frames", "local_maps", "tracking_failures",
                         "tracking_failure_reasons", "tracking_searched", "tracking_ambiguous",
                         "tracking_hypotheses", "tracking_unchecked", "tracking_unchecked_frames",
                         "tracking_time_s", "module_errors", "reference", "graph",
                         "locked_on_after_frames", "modules", "statistics"}));
  // Every reason is a key, in the tracker's order, a zero count included (issue 20).
  EXPECT_EQ(keys(j["tracking_failure_reasons"]),
            (std::vector<std::string>{"no_data", "too_few_inliers", "degenerate"}));
  EXPECT_EQ(j["tracking_failure_reasons"]["too_few_inliers"], 2);
  EXPECT_EQ(keys(j["reference"]),
            (std::vector<std::string>{"ate_rmse_m", "ate_max_m", "rpe_1m_rmse_m"}));
  EXPECT_EQ(keys(j["graph"]),
            (std::vector<std::string>{"nodes", "edges", "loop_candidates", "loops_accepted",
                                      "loops_rejected", "loops_restored", "optimizations",
                                      "optimization_time_s", "loop_detection_time_s",
                                      "loop_validation_time_s", "final_chi2", "components"}));
  EXPECT_EQ(keys(j["modules"]), (std::vector<std::string>{"source", "pipeline.tracker"}));
  EXPECT_EQ(j["frames"].get<uint64_t>(), 996u);
  // Seconds keep 6 decimals, rates 3, mean_ms 4: the values the hand-written writer printed.
  EXPECT_EQ(j["wall_time_s"].get<double>(), 1.264362);
  EXPECT_EQ(j["hz"].get<double>(), 787.749);
  EXPECT_EQ(j["pipeline_hz"].get<double>(), 1382.086);
  EXPECT_EQ(j["graph"]["final_chi2"].get<double>(), 14.060293);
  EXPECT_EQ(j["reference"]["ate_rmse_m"].get<double>(), 0.001372);
  EXPECT_EQ(j["modules"]["source"]["mean_ms"].get<double>(), 0.3397);
  EXPECT_EQ(j["modules"]["source"]["calls"].get<uint64_t>(), 997u);
  EXPECT_EQ(j["stopped_by"], "end of data");
  EXPECT_TRUE(j["error"].is_null());
  // The readers' string and regex probes (fault_test, slam_integration_test) still match.
  EXPECT_NE(text.find("\"frames\": 996,"), std::string::npos) << text;
  EXPECT_NE(text.find("\"stopped_by\": \"end of data\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"loops_accepted\": 64"), std::string::npos) << text;
  EXPECT_EQ(text.back(), '\n');
}

TEST(RunReportJson, MissingOrNonFiniteFiguresAreNull) {
  RunReport r = sampleReport();
  r.ate_rmse.reset();
  r.ate_max = std::numeric_limits<double>::quiet_NaN();
  r.rpe_rmse = std::numeric_limits<double>::infinity();
  r.graph.final_chi2 = std::numeric_limits<double>::quiet_NaN();
  r.hz = std::numeric_limits<double>::infinity();
  const ordered_json j = ordered_json::parse(runReportJson(r));  // throws on NaN / inf tokens
  EXPECT_TRUE(j["reference"]["ate_rmse_m"].is_null());
  EXPECT_TRUE(j["reference"]["ate_max_m"].is_null());
  EXPECT_TRUE(j["reference"]["rpe_1m_rmse_m"].is_null());
  EXPECT_TRUE(j["graph"]["final_chi2"].is_null());
  EXPECT_TRUE(j["hz"].is_null());
}

TEST(RunReportJson, StatisticsByModuleWithSixDecimalsAndNullWhereNotFinite) {
  RunReport r = sampleReport();
  EXPECT_TRUE(ordered_json::parse(runReportJson(r))["statistics"].empty());  // none: {}
  r.statistics = {{"pipeline.tracker.aligner.slices[0]",
                   {{"matches_per_frame", 412.3456789},
                    {"alignment_s", 0.0012345678},
                    {"ratio", std::numeric_limits<double>::quiet_NaN()}}},
                  {"pipeline.tracker", {{"landmarks", 3.0}}}};
  const ordered_json j = ordered_json::parse(runReportJson(r));
  EXPECT_EQ(keys(j["statistics"]),
            (std::vector<std::string>{"pipeline.tracker.aligner.slices[0]", "pipeline.tracker"}));
  const ordered_json& s = j["statistics"]["pipeline.tracker.aligner.slices[0]"];
  EXPECT_EQ(keys(s), (std::vector<std::string>{"matches_per_frame", "alignment_s", "ratio"}));
  EXPECT_EQ(s["matches_per_frame"].get<double>(), 412.345679);
  EXPECT_EQ(s["alignment_s"].get<double>(), 0.001235);
  EXPECT_TRUE(s["ratio"].is_null());
  EXPECT_EQ(j["statistics"]["pipeline.tracker"]["landmarks"].get<double>(), 3.0);
}

TEST(RunReportJson, ErrorMessagesAreEscapedEvenWithBytesThatAreNotUtf8) {
  RunReport r = sampleReport();
  r.stopped_by = "error";
  r.error = std::string("bad \"line\"\n\tat C:\\x \x01 and \xff\xfe bytes");
  const ordered_json j = ordered_json::parse(runReportJson(r));
  const std::string e = j["error"].get<std::string>();
  EXPECT_EQ(e.substr(0, 25), "bad \"line\"\n\tat C:\\x \x01 and");
  EXPECT_NE(e.find("\xEF\xBF\xBD"), std::string::npos) << "invalid bytes become U+FFFD";
}

}  // namespace
}  // namespace plugslam::runtime
