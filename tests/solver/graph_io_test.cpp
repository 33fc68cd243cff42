#include "plugslam/solver/graph_io.h"

#include <gtest/gtest.h>

#include <cmath>
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
  EXPECT_EQ(info.edge2_information_order, "toro");
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

namespace {

// "x y z roll pitch yaw" of a pose for a TORO / HOG-Man 3D file (R = Rz(yaw) Ry(pitch) Rx(roll)).
std::string toroPose(const SE3& x) {
  const Eigen::Vector3d ypr = x.linear().eulerAngles(2, 1, 0);
  std::ostringstream out;
  out.precision(17);
  out << x.translation().x() << ' ' << x.translation().y() << ' ' << x.translation().z() << ' '
      << ypr[2] << ' ' << ypr[1] << ' ' << ypr[0];
  return out.str();
}

}  // namespace

// Issue 21: the 3D TORO / HOG-Man format (GTSAM's sphere2500.txt). A graph made here is written
// both as g2o and as TORO 3D (its information over the error's roll/pitch/yaw, which are twice
// the quaternion vector part g2o's EDGE_SE3:QUAT uses); both files read as the same graph.
TEST(GraphIo, ReadsToro3DAsTheSameGraphAsG2o) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  FactorGraph g;
  const int n = 6;
  for (int i = 0; i < n; ++i) {
    Vector6d v;
    for (int q = 0; q < 6; ++q) v[q] = 2.0 * u(rng);
    g.addVariable<VariableSE3>(i, se3(v));
  }
  g.get<VariableSE3>(0).setFixed(true);
  std::ostringstream toro;
  toro.precision(17);
  for (int i = 0; i < n; ++i)
    toro << "VERTEX3 " << i << ' ' << toroPose(g.get<VariableSE3>(i).estimate()) << '\n';
  toro << "FIX 0\n";
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;  // a ring: one loop
    Vector6d v;
    for (int q = 0; q < 6; ++q) v[q] = u(rng);
    Eigen::Matrix<double, 6, 6> a;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) a(r, c) = u(rng);
    const Eigen::Matrix<double, 6, 6> info =
        a * a.transpose() + Eigen::Matrix<double, 6, 6>::Identity();
    const SE3 z = se3(v);
    g.emplaceFactor<BetweenFactorSE3>(&g.get<VariableSE3>(i), &g.get<VariableSE3>(j), z, info);
    // TORO's information: the rotation rows and columns over angles, half of g2o's per index.
    Eigen::Matrix<double, 6, 6> d = Eigen::Matrix<double, 6, 6>::Identity();
    d.diagonal().tail<3>().setConstant(0.5);
    const Eigen::Matrix<double, 6, 6> toro_info = d * info * d;
    toro << "EDGE3 " << i << ' ' << j << ' ' << toroPose(z);
    for (int r = 0; r < 6; ++r)
      for (int c = r; c < 6; ++c) toro << ' ' << toro_info(r, c);
    toro << '\n';
  }
  const plugslam::testing::TempDir tmp;
  const std::string g2o_path = tmp.file("ring.g2o");
  writeGraphFile(g2o_path, g);
  const std::string toro_path = tmp.write("ring.graph", toro.str());
  FactorGraph from_g2o, from_toro;
  readGraphFile(g2o_path, from_g2o);
  const GraphFileInfo info = readGraphFile(toro_path, from_toro);
  EXPECT_EQ(info.format, "toro");
  EXPECT_EQ(info.dimension, 3);
  EXPECT_EQ(info.vertices, size_t(n));
  EXPECT_EQ(info.edges, size_t(n));
  EXPECT_EQ(info.fixed, 1u);
  EXPECT_EQ(info.non_pd_information, 0u);
  ASSERT_EQ(from_toro.numVariables(), from_g2o.numVariables());
  ASSERT_EQ(from_toro.numFactors(), from_g2o.numFactors());
  // Bounds: the files print 17 digits, so the only differences are the Euler round trip's
  // rounding (~1e-15); 1e-12 fails on any convention error (those are O(1)).
  for (size_t k = 0; k < from_g2o.numVariables(); ++k) {
    const auto& a = static_cast<const VariableSE3&>(*from_g2o.variables()[k]);
    const auto& b = static_cast<const VariableSE3&>(*from_toro.variables()[k]);
    EXPECT_EQ(a.id(), b.id());
    EXPECT_EQ(a.fixed(), b.fixed());
    EXPECT_LT((a.estimate().matrix() - b.estimate().matrix()).norm(), 1e-12) << k;
  }
  for (size_t k = 0; k < from_g2o.numFactors(); ++k) {
    const auto& a = dynamic_cast<const BetweenFactorSE3&>(*from_g2o.factors()[k]);
    const auto& b = dynamic_cast<const BetweenFactorSE3&>(*from_toro.factors()[k]);
    EXPECT_LT((a.measurement().matrix() - b.measurement().matrix()).norm(), 1e-12) << k;
    EXPECT_LT((a.information() - b.information()).norm(), 1e-12 * a.information().norm()) << k;
  }
}

// The rotation convention, checked by the axes (independent of how the reader composes it).
TEST(GraphIo, Toro3DAnglesAreRollPitchYawAboutFixedAxes) {
  const double h = M_PI / 2;
  std::ostringstream text;
  text.precision(17);
  text << "VERTEX3 0 1 2 3 " << h << " 0 0\n"             // roll: y -> z
       << "VERTEX3 1 0 0 0 0 " << h << " 0\n"             // pitch: x -> -z
       << "VERTEX3 2 0 0 0 0 0 " << h << "\n"             // yaw: x -> y
       << "VERTEX3 3 0 0 0 0 " << h << ' ' << h << "\n";  // Rz Ry: x -> -z (Ry Rz would give y)
  FactorGraph g;
  const GraphFileInfo info = readString(text.str(), g);
  EXPECT_EQ(info.dimension, 3);
  EXPECT_EQ(info.format, "toro");
  auto axis = [&](int id, const Eigen::Vector3d& v) {
    return Eigen::Vector3d(g.get<VariableSE3>(id).estimate().linear() * v);
  };
  EXPECT_LT((g.get<VariableSE3>(0).estimate().translation() - Eigen::Vector3d(1, 2, 3)).norm(),
            1e-15);
  EXPECT_LT((axis(0, Eigen::Vector3d::UnitY()) - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((axis(1, Eigen::Vector3d::UnitX()) + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
  EXPECT_LT((axis(2, Eigen::Vector3d::UnitX()) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_LT((axis(3, Eigen::Vector3d::UnitX()) + Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}

TEST(GraphIo, Toro3DInformationIsOverTheErrorsAngles) {
  // sphere2500's noise: 10 per m^2 in translation, 100 per rad^2 in rotation; over the
  // quaternion's vector part (half the angle) that is 400, as SE-Sync's sphere2500.g2o has it.
  FactorGraph g;
  const GraphFileInfo info = readString(
      "VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 1 0 0 0 0 0.1\n"
      "EDGE3 0 1 1 0 0 0 0 0.1 10 0 0 0 0 0 10 0 0 0 0 10 0 0 0 100 0 0 100 0 100\n",
      g);
  EXPECT_EQ(info.non_pd_information, 0u);
  const auto& e = dynamic_cast<const BetweenFactorSE3&>(*g.factors()[0]);
  Eigen::Matrix<double, 6, 1> expected;
  expected << 10, 10, 10, 400, 400, 400;
  EXPECT_LT((e.information() - Eigen::Matrix<double, 6, 6>(expected.asDiagonal())).norm(), 1e-12);
  EXPECT_LT((e.measurement().translation() - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
}

TEST(GraphIo, MalformedToro3DGivesLineNumbers) {
  const std::string v = "VERTEX3 0 0 0 0 0 0 0\nVERTEX3 1 1 0 0 0 0 0\n";
  const std::string info21 = " 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1";
  expectParseError("VERTEX3 0 0 0 0 0 0\n", 1, "truncated");
  expectParseError("VERTEX3 0 0 0 0 0 0 nan\n", 1, "non-finite");
  expectParseError("VERTEX3 0 0 0 0 0 0 0 1\n", 1, "extra value");
  expectParseError("VERTEX2 0 0 0 0\nVERTEX3 1 0 0 0 0 0 0\n", 2, "3D record");
  expectParseError("VERTEX3 0 0 0 0 0 0 0\nEDGE2 0 1 1 0 0 1 0 1 1 0 0\n", 2, "2D record");
  expectParseError(v + "EDGE3 0 1 1 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0\n", 3,
                   "truncated");
  expectParseError(v + "EDGE3 0 1 1 0 0 0 0 0" + info21 + " 7\n", 3, "extra value");
  expectParseError(v + "EDGE3 0 9 1 0 0 0 0 0" + info21 + "\n", 3, "vertex 9");
  expectParseError(v + "EDGE3 0 1 1 0 0 0 0 inf" + info21 + "\n", 3, "non-finite");
  // An information that is not positive definite is counted, as for every other edge type.
  FactorGraph g;
  const GraphFileInfo info =
      readString(v + "EDGE3 0 1 1 0 0 0 0 0 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 -1\n", g);
  EXPECT_EQ(info.non_pd_information, 1u);
}

// Issue 21: EDGE2 written in g2o's information order (GTSAM's w20000.txt). A diagonal
// information in g2o's order reads as TORO's with yy = 0: not positive definite.
TEST(GraphIo, Edge2InG2osInformationOrderIsReadSoWhenOnlyThatOrderFits) {
  FactorGraph g;
  const GraphFileInfo info = readString(
      "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nVERTEX2 2 2 0 0\n"
      "EDGE2 0 1 1 0 0 100 0 0 100 0 1000\n"
      "EDGE2 1 2 1 0 0 100 1 2 100 3 1000\n",  // g2o: xx xy xt yy yt tt
      g);
  EXPECT_EQ(info.format, "toro");
  EXPECT_EQ(info.edge2_information_order, "g2o");
  EXPECT_EQ(info.non_pd_information, 0u);
  const auto& e = dynamic_cast<const BetweenFactorSE2&>(*g.factors()[1]);
  Eigen::Matrix3d expected;
  expected << 100, 1, 2, 1, 100, 3, 2, 3, 1000;
  EXPECT_TRUE(e.information() == expected) << e.information();
}

TEST(GraphIo, Edge2KeepsToroOrderUnlessOnlyG2osFitsEveryEdge) {
  const std::string vertices = "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0\nVERTEX2 2 2 0 0\n";
  {
    // Both orders positive definite: TORO's, the format's own.
    FactorGraph g;
    const GraphFileInfo info = readString(vertices + "EDGE2 0 1 1 0 0 10 0 2 10 0 2\n", g);
    EXPECT_EQ(info.edge2_information_order, "toro");
    const Eigen::Matrix3d& m = dynamic_cast<const BetweenFactorSE2&>(*g.factors()[0]).information();
    EXPECT_EQ(m(1, 1), 2.0);  // g2o's order would give 10
    EXPECT_EQ(m(0, 2), 0.0);  // g2o's order would give 2
  }
  {
    // One edge fits only TORO's order, the other only g2o's: no order fits every edge, so
    // TORO's stays and the other edge is counted (optimize refuses it, as before).
    FactorGraph g;
    const GraphFileInfo info = readString(vertices +
                                              "EDGE2 0 1 1 0 0 100 0 100 1000 0 0\n"
                                              "EDGE2 1 2 1 0 0 100 0 0 100 0 1000\n",
                                          g);
    EXPECT_EQ(info.edge2_information_order, "toro");
    EXPECT_EQ(info.non_pd_information, 1u);
  }
  {
    // No EDGE2 at all: nothing to decide.
    FactorGraph g;
    EXPECT_EQ(readString(kGraph2D, g).edge2_information_order, "");
  }
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
