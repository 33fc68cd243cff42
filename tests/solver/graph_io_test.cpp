#include "plugslam/solver/graph_io.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

#include "plugslam/errors.h"
#include "plugslam/solver/pose_factors.h"
#include "temp_dir.h"

using namespace plugslam;

namespace {

GraphFileInfo readString(const std::string& text, FactorGraph& g, const ReadGraphOptions& o = {}) {
  std::istringstream in(text);
  return readGraph(in, "test.g2o", g, o);
}

// Expects a ParseError at the given line whose message contains `what`.
void expectParseError(const std::string& text, int line, const std::string& what) {
  FactorGraph g;
  try {
    readString(text, g);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.file(), "test.g2o");
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
  }
}

const char* kGraph2D =
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1 0 0.1\n"
    "VERTEX_SE2 2 2 0.1 0.2\n"
    "FIX 0\n"
    "EDGE_SE2 0 1 1 0 0.1 100 0 0 100 0 1000\n"
    "EDGE_SE2 1 2 1 0.1 0.1 100 1 2 100 3 1000\n";

}  // namespace

TEST(GraphIo, Reads2D) {
  FactorGraph g;
  const GraphFileInfo info = readString(kGraph2D, g);
  EXPECT_EQ(info.dimension, 2);
  EXPECT_EQ(info.vertices, 3u);
  EXPECT_EQ(info.edges, 2u);
  EXPECT_EQ(info.fixed, 1u);
  EXPECT_TRUE(info.has_vertices);
  EXPECT_EQ(info.non_pd_information, 0u);
  EXPECT_TRUE(g.get<VariableSE2>(0).fixed());
  const auto* e = dynamic_cast<const BetweenFactorSE2*>(g.factors()[1].get());
  ASSERT_NE(e, nullptr);
  EXPECT_DOUBLE_EQ(e->information()(0, 1), 1.0);
  EXPECT_DOUBLE_EQ(e->information()(1, 0), 1.0);
  EXPECT_DOUBLE_EQ(e->information()(0, 2), 2.0);
  EXPECT_DOUBLE_EQ(e->information()(1, 2), 3.0);
  EXPECT_DOUBLE_EQ(e->information()(2, 2), 1000.0);
}

TEST(GraphIo, RoundTrip2DAnd3D) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int dim : {2, 3}) {
    FactorGraph g;
    for (int k = 0; k < 20; ++k) {
      if (dim == 2) {
        g.addVariable<VariableSE2>(k * 7, se2(10 * u(rng), 10 * u(rng), 3 * u(rng)));
      } else {
        Vector6d v;
        for (int i = 0; i < 6; ++i) v[i] = (i < 3 ? 10 : 1.5) * u(rng);
        g.addVariable<VariableSE3>(k * 7, se3(v));
      }
    }
    g.variables()[0]->setFixed(true);
    for (int k = 0; k < 30; ++k) {
      const int i = k % 20, j = (k * 7 + 3) % 20;
      if (i == j) continue;
      if (dim == 2) {
        Eigen::Matrix3d a = Eigen::Matrix3d::Random();
        g.emplaceFactor<BetweenFactorSE2>(&g.get<VariableSE2>(i * 7), &g.get<VariableSE2>(j * 7),
                                          se2(u(rng), u(rng), 3 * u(rng)),
                                          a * a.transpose() + Eigen::Matrix3d::Identity());
      } else {
        Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Random();
        Vector6d v;
        for (int q = 0; q < 6; ++q) v[q] = u(rng);
        g.emplaceFactor<BetweenFactorSE3>(
            &g.get<VariableSE3>(i * 7), &g.get<VariableSE3>(j * 7), se3(v),
            a * a.transpose() + Eigen::Matrix<double, 6, 6>::Identity());
      }
    }
    const plugslam::testing::TempDir tmp;
    const std::string path = tmp.file("roundtrip" + std::to_string(dim) + ".g2o");
    EXPECT_EQ(writeGraphFile(path, g), 0u);
    FactorGraph r;
    const GraphFileInfo info = readGraphFile(path, r);
    std::remove(path.c_str());
    EXPECT_EQ(info.dimension, dim);
    ASSERT_EQ(r.numVariables(), g.numVariables());
    ASSERT_EQ(r.numFactors(), g.numFactors());
    for (size_t k = 0; k < g.numVariables(); ++k) {
      EXPECT_EQ(r.variables()[k]->id(), g.variables()[k]->id());
      EXPECT_EQ(r.variables()[k]->fixed(), g.variables()[k]->fixed());
    }
    for (size_t k = 0; k < g.numFactors(); ++k) {
      const FactorBase& a = *g.factors()[k];
      const FactorBase& b = *r.factors()[k];
      EXPECT_EQ(a.variable(0)->id(), b.variable(0)->id());
      EXPECT_EQ(a.variable(1)->id(), b.variable(1)->id());
      // Same estimates and measurements give the same error and chi2.
      EXPECT_LT((a.errorVector() - b.errorVector()).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_NEAR(a.chi2(), b.chi2(), 1e-9 * (1 + a.chi2()));
    }
    if (dim == 2) {
      for (size_t k = 0; k < g.numVariables(); ++k) {
        EXPECT_LT((static_cast<VariableSE2*>(g.variables()[k])->estimate().matrix() -
                   static_cast<VariableSE2*>(r.variables()[k])->estimate().matrix())
                      .norm(),
                  1e-14);
      }
    } else {
      for (size_t k = 0; k < g.numVariables(); ++k) {
        EXPECT_LT((static_cast<VariableSE3*>(g.variables()[k])->estimate().matrix() -
                   static_cast<VariableSE3*>(r.variables()[k])->estimate().matrix())
                      .norm(),
                  1e-14);
      }
    }
  }
}

TEST(GraphIo, ReadsToroWithItsInformationOrder) {
  FactorGraph g;
  // TORO: xx xy yy tt xt yt.
  const GraphFileInfo info = readString(
      "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\n# comment\nEDGE2 0 1 1 0 0 11 12 22 33 13 23\n", g);
  EXPECT_EQ(info.format, "toro");
  const auto* e = dynamic_cast<const BetweenFactorSE2*>(g.factors()[0].get());
  ASSERT_NE(e, nullptr);
  const Eigen::Matrix3d& m = e->information();
  EXPECT_EQ(m(0, 0), 11);
  EXPECT_EQ(m(0, 1), 12);
  EXPECT_EQ(m(1, 1), 22);
  EXPECT_EQ(m(2, 2), 33);
  EXPECT_EQ(m(0, 2), 13);
  EXPECT_EQ(m(1, 2), 23);
  EXPECT_EQ(m(2, 0), 13);
}

TEST(GraphIo, EdgeOnlyFilesCreateVertices) {
  FactorGraph g;
  const GraphFileInfo info = readString(
      "EDGE_SE2 5 6 1 0 0 1 0 0 1 0 1\nEDGE_SE2 6 7 1 0 0 1 0 0 1 0 1\nEDGE_SE2 5 7 2 0 0 1 0 0 1 "
      "0 1\n",
      g);
  EXPECT_FALSE(info.has_vertices);
  ASSERT_EQ(g.numVariables(), 3u);
  EXPECT_EQ(g.variables()[0]->id(), 5);
  EXPECT_EQ(g.variables()[2]->id(), 7);
}

TEST(GraphIo, MalformedInputGivesLineNumbers) {
  expectParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0\n", 2, "truncated");
  expectParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 nan\n", 2, "non-finite");
  expectParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 inf\n", 2, "non-finite");
  expectParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 0 1 0 0\n", 2, "duplicate vertex id 0");
  expectParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2 0 9 1 0 0 1 0 0 1 0 1\n", 3,
                   "vertex 9");
  expectParseError("VERTEX_SE2 99999999999999999999999 0 0 0\n", 1, "out of range");
  expectParseError("VERTEX_SE2 1e30 0 0 0\n", 1, "integer id");
  expectParseError("VERTEX_SE2 0 0 0 0\n\x01\x02\xff\xfe garbage\n", 2, "binary");
  expectParseError("VERTEX_SE2 0 0 0 0\n\xff\xfe\xfd\n", 2, "unknown record");
  expectParseError("VERTEX_SE2 0 0 0 0 7\n", 1, "extra value");
  expectParseError("VERTEX_SE2 0 0 0 0\nVERTEX_SE3:QUAT 1 0 0 0 0 0 0 1\n", 2, "3D record");
  expectParseError("VERTEX_SE3:QUAT 1 0 0 0 0 0 0 0\n", 1, "zero norm");
  expectParseError("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 0 1 0 0 1 0 0 1 0 1\n", 2, "itself");
  expectParseError("VERTEX_SE2 0 0 0 0\nFIX 4\n", 2, "FIX");
  expectParseError("VERTEX_SE2 0 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0\n", 2, "truncated");
  expectParseError("", 0, "no vertex or edge");
  expectParseError("# only a comment\n", 0, "no vertex or edge");
}

TEST(GraphIo, TruncatedRealFileAtEveryByteNeverCrashes) {
  // Every prefix of a valid file either parses or throws ParseError.
  const std::string text = kGraph2D;
  for (size_t n = 0; n < text.size(); ++n) {
    FactorGraph g;
    try {
      readString(text.substr(0, n), g);
    } catch (const ParseError&) {
    }
  }
  SUCCEED();
}

TEST(GraphIo, RandomBinaryGarbageIsRejected) {
  std::mt19937 rng(3);
  for (int k = 0; k < 50; ++k) {
    std::string s(200, '\0');
    for (char& c : s) c = char(rng());
    FactorGraph g;
    EXPECT_THROW(readString(s, g), ParseError);
  }
}

TEST(GraphIo, NonPositiveDefiniteInformationIsCountedAndProjectedOnRequest) {
  const std::string text =
      "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\n"
      "EDGE_SE2 0 1 1 0 0 1 0 0 1 0 -1\n"  // indefinite
      "EDGE_SE2 1 2 1 0 0 1 2 0 1 0 1\n"   // indefinite (off-diagonal too large)
      "EDGE_SE2 0 2 2 0 0 1 0 0 1 0 1\n";  // fine
  FactorGraph g;
  GraphFileInfo info = readString(text, g);
  EXPECT_EQ(info.non_pd_information, 2u);
  EXPECT_EQ(info.projected_information, 0u);
  EXPECT_EQ(dynamic_cast<const BetweenFactorSE2&>(*g.factors()[0]).information()(2, 2), -1.0);
  FactorGraph p;
  ReadGraphOptions o;
  o.project_information = true;
  info = readString(text, p, o);
  EXPECT_EQ(info.non_pd_information, 2u);
  EXPECT_EQ(info.projected_information, 2u);
  for (const auto& f : p.factors()) {
    EXPECT_TRUE(isPositiveDefinite(dynamic_cast<const BetweenFactorSE2&>(*f).information()));
  }
}

TEST(GraphIo, NearestPositiveDefiniteKeepsPdMatrices) {
  Eigen::Matrix3d a;
  a << 4, 1, 0, 1, 3, 0.5, 0, 0.5, 2;
  EXPECT_LT((nearestPositiveDefinite(a) - a).norm(), 1e-12);
  Eigen::Matrix3d b = Eigen::Vector3d(2, -1, 0).asDiagonal();
  const Eigen::MatrixXd c = nearestPositiveDefinite(b);
  EXPECT_TRUE(isPositiveDefinite(c));
  EXPECT_NEAR(c(0, 0), 2.0, 1e-12);
}

TEST(GraphIo, MissingFileIsAnInputError) {
  FactorGraph g;
  EXPECT_THROW(readGraphFile("/nonexistent/graph.g2o", g), InputError);
}
