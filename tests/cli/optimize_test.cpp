// `plugslam optimize` as a user runs it: the iteration table, the written graph (read back with
// the solver's reader), the JSON summary, exit codes (0 ok, 2 bad input) and a real graph.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "plugslam/solver/factor_graph.h"
#include "plugslam/solver/graph_io.h"
#include "plugslam/solver/variable.h"
#include "run_command.h"
#include "temp_dir_test.h"
#include "test_paths.h"

namespace fs = std::filesystem;

namespace {

using Result = plugslam::testing::CommandResult;
using plugslam::testing::expectHas;

Result run(const std::string& args) {
  return plugslam::testing::runCommand(plugslam::testing::buildDir() + "/bin/plugslam " + args);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The number after "key": in a flat JSON object; NaN when absent.
double jsonNumber(const std::string& json, const std::string& key) {
  const std::string tag = "\"" + key + "\": ";
  const size_t at = json.find(tag);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + tag.size(), nullptr);
}

class Optimize : public plugslam::testing::TempDirTest {
 protected:
  Optimize() : TempDirTest("plugslam_optimize") {}
};

// A 2D loop of 8 poses around a square, 1 m apart, with exact odometry and one exact loop
// closure, so the optimum is chi2 = 0 at the true poses. The vertex estimates are perturbed.
std::string squareLoop2d() {
  std::ostringstream g;
  const double x[] = {0, 1, 2, 2, 2, 1, 0, 0};
  const double y[] = {0, 0, 0, 1, 2, 2, 2, 1};
  const double th[] = {0, 0, M_PI / 2, M_PI / 2, M_PI, M_PI, -M_PI / 2, -M_PI / 2};
  for (int i = 0; i < 8; ++i) {
    g << "VERTEX_SE2 " << i << " " << x[i] + 0.1 * std::sin(i) << " " << y[i] - 0.1 * std::cos(i)
      << " " << th[i] + 0.05 * i << "\n";
  }
  g.precision(17);
  for (int i = 0; i < 8; ++i) {
    const int j = (i + 1) % 8;
    const double dx = x[j] - x[i], dy = y[j] - y[i];
    const double c = std::cos(th[i]), s = std::sin(th[i]);
    double dth = th[j] - th[i];
    dth = std::atan2(std::sin(dth), std::cos(dth));
    g << "EDGE_SE2 " << i << " " << j << " " << c * dx + s * dy << " " << -s * dx + c * dy << " "
      << dth << " 100 0 0 100 0 400\n";
  }
  return g.str();
}

// A 3D chain of 5 poses with one loop closure; identity rotations, exact measurements.
std::string chain3d() {
  std::ostringstream g;
  for (int i = 0; i < 5; ++i)
    g << "VERTEX_SE3:QUAT " << i << " " << i + 0.05 * i << " " << 0.02 * i << " 0 0 0 0 1\n";
  const std::string info = " 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 40 0 0 40 0 40\n";
  for (int i = 0; i < 4; ++i)
    g << "EDGE_SE3:QUAT " << i << " " << i + 1 << " 1 0 0 0 0 0 1" << info;
  g << "EDGE_SE3:QUAT 0 4 4 0 0 0 0 0 1" << info;
  return g.str();
}

}  // namespace

TEST_F(Optimize, SmallGraphReachesTheKnownOptimumAndWritesGraphAndSummary) {
  const std::string in = write("square.g2o", squareLoop2d());
  const std::string out = path("square_out.g2o");
  const Result r = run("optimize " + in + " -o " + out + " --init file --solver gn");
  ASSERT_EQ(r.code, 0) << r.out;
  for (auto col : {"iter", "chi2", "linearize", "solve", "update", "SE-Sync objective"})
    expectHas(r.out, col);

  plugslam::FactorGraph graph;
  const plugslam::GraphFileInfo info = plugslam::readGraphFile(out, graph);
  EXPECT_EQ(info.dimension, 2);
  EXPECT_EQ(info.vertices, 8u);
  EXPECT_EQ(info.edges, 8u);
  EXPECT_LT(graph.chi2(), 1e-8);
  // The gauge keeps pose 0 where the file put it; the rest follows the exact measurements.
  const auto* p0 = dynamic_cast<const plugslam::VariableSE2*>(graph.variables().front());
  const auto* p4 = dynamic_cast<const plugslam::VariableSE2*>(graph.variables()[4]);
  ASSERT_TRUE(p0 && p4);
  const plugslam::SE2 rel = p0->estimate().inverse() * p4->estimate();
  EXPECT_NEAR(rel.translation().x(), 2.0, 1e-6);
  EXPECT_NEAR(rel.translation().y(), 2.0, 1e-6);
  EXPECT_NEAR(std::abs(Eigen::Rotation2Dd(rel.rotation()).angle()), M_PI, 1e-6);

  const std::string json = slurp(out + ".json");
  ASSERT_FALSE(json.empty()) << "no summary at " << out << ".json";
  for (auto key : {"poses", "edges", "initial_chi2", "final_chi2", "iterations", "time_optimize",
                   "time_total", "se_sync_objective"}) {
    EXPECT_FALSE(std::isnan(jsonNumber(json, key))) << key << " missing in " << json;
  }
  EXPECT_EQ(jsonNumber(json, "poses"), 8);
  EXPECT_EQ(jsonNumber(json, "edges"), 8);
  EXPECT_GT(jsonNumber(json, "initial_chi2"), 1.0);
  EXPECT_LT(jsonNumber(json, "final_chi2"), 1e-8);
  EXPECT_GE(jsonNumber(json, "iterations"), 1);
  expectHas(json, "\"per_iteration\": [{\"iteration\": 0");
  expectHas(json, "\"solver\": \"gn\"");
}

TEST_F(Optimize, LevenbergMarquardtOn3dWithSummaryPathAndQuiet) {
  const std::string in = write("chain.g2o", chain3d());
  const std::string out = path("chain_out.g2o"), summary = path("summary.json");
  const Result r =
      run("optimize " + in + " -o " + out +
          " --solver lm --init odometry --iterations 50 --factorization supernodal --summary " +
          summary + " -q");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(r.out.find("linearize"), std::string::npos) << "-q still printed the table:\n" << r.out;
  EXPECT_FALSE(fs::exists(out + ".json"));
  const std::string json = slurp(summary);
  EXPECT_LT(jsonNumber(json, "final_chi2"), 1e-10) << json;
  expectHas(json, "\"solver\": \"lm\"");
  expectHas(json, "\"init\": \"odometry\"");
  expectHas(json, "\"factorization\": \"supernodal\"");
  EXPECT_EQ(jsonNumber(json, "dimension"), 3);

  plugslam::FactorGraph graph;
  EXPECT_EQ(plugslam::readGraphFile(out, graph).vertices, 5u);
  EXPECT_LT(graph.chi2(), 1e-10);
}

TEST_F(Optimize, EdgeOnlyFileIsInitialisedAndRobustKernelAccepted) {
  std::string edges = squareLoop2d();
  std::string only;
  std::istringstream lines(edges);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("EDGE", 0) == 0) only += line + "\n";
  const std::string in = write("edges.g2o", only);
  const std::string out = path("edges_out.g2o");
  const Result r =
      run("optimize " + in + " -o " + out + " --init best --robust Huber --robust-scale 2");
  ASSERT_EQ(r.code, 0) << r.out;
  expectHas(r.out, "edges only");
  expectHas(r.out, "start 2: chordal");
  plugslam::FactorGraph graph;
  EXPECT_EQ(plugslam::readGraphFile(out, graph).vertices, 8u);
  EXPECT_LT(graph.chi2(), 1e-8);
}

TEST_F(Optimize, MalformedInputExitsTwoWithFileAndLine) {
  const std::string in =
      write("bad.g2o",
            "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 1 1 0 zero 1 0 0 "
            "1 0 1\n");
  const Result r = run("optimize " + in + " -o " + path("bad_out.g2o"));
  expectExit(r, 2, {in + ":3"});
  EXPECT_FALSE(fs::exists(path("bad_out.g2o")));
  EXPECT_FALSE(fs::exists(path("bad_out.g2o.json")));
}

TEST_F(Optimize, BadArgumentsExitTwo) {
  const std::string in = write("square.g2o", squareLoop2d());
  // The arguments, and what the message must name ("": only the exit code is checked).
  const std::pair<std::string, std::string> cases[] = {
      {path("missing.g2o") + " -o " + path("o.g2o"), "missing.g2o"},
      {in + " --solver newton", "--solver: newton not in {gn,lm}"},
      {in + " --init spanning", "--init: spanning not in {file,odometry,chordal,best}"},
      {in + " --robust Welsch", "Huber"},
      {in + " --factorization qr", "--factorization: qr not in {auto,supernodal,simplicial,block}"},
      {in + " --iterations -3", ""},
      {in + " -o " + path("no/such/dir/out.g2o"), ""},
      {in + " --summary " + path("no/such/dir/s.json"), "--summary"},
      {"", ""},
  };
  for (const auto& [args, names] : cases) {
    const Result r = run("optimize " + args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    if (!names.empty()) expectHas(r.out, names);
  }
}

TEST_F(Optimize, NonPositiveDefiniteInformationRefusedUnlessProjected) {
  const std::string in = write("nonpd.g2o",
                               "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
                               "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 -1\nEDGE_SE2 1 2 1 0 0 1 0 0 1 0 1\n"
                               "EDGE_SE2 0 2 2 0 0.1 1 0 0 1 0 1\n");
  Result r = run("optimize " + in + " -o " + path("o.g2o"));
  expectExit(r, 2, {"1 of 3 edges", "--project-information"});
  r = run("optimize " + in + " -o " + path("o.g2o") + " --project-information");
  expectExit(r, 0, {"projected 1 of 3"});
  EXPECT_EQ(jsonNumber(slurp(path("o.g2o.json")), "projected_information"), 1);
}

TEST_F(Optimize, ChordalOnRealGraphsReachesTheBestKnownChi2) {
  // Best known chi2 (g2o's definition) from issue 3's table; chordal must reach it, where
  // g2o GN from MIT's own poses stops at 770.66.
  struct Case {
    const char* file;
    double max_chi2;
  };
  int ran = 0;
  for (const Case& c : {Case{"posegraph/se-sync/intel.g2o", 45.005 * 1.001},
                        Case{"posegraph/se-sync/MIT.g2o", 526.33}}) {
    const std::string in = plugslam::testing::dataDir() + "/" + c.file;
    if (!fs::exists(in)) continue;
    ++ran;
    const std::string out = path("real_out.g2o");
    const Result r = run("optimize " + in + " -o " + out + " --init chordal -q");
    ASSERT_EQ(r.code, 0) << c.file << "\n" << r.out;
    const std::string json = slurp(out + ".json");
    EXPECT_LT(jsonNumber(json, "final_chi2"), c.max_chi2) << c.file << ": " << json;
    EXPECT_GT(jsonNumber(json, "se_sync_objective"), 0.0) << json;
    plugslam::FactorGraph graph;
    plugslam::readGraphFile(out, graph);
    EXPECT_NEAR(graph.chi2(), jsonNumber(json, "final_chi2"), 1e-6 * (1 + graph.chi2()))
        << "the written graph does not hold the reported optimum";
  }
  if (ran == 0) GTEST_SKIP() << "PLUGSLAM_DATA/posegraph/se-sync/{intel,MIT}.g2o not available";
}
