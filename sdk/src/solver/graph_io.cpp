#include "plugslam/solver/graph_io.h"

#include <spdlog/spdlog.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"
#include "plugslam/solver/pose_factors.h"

namespace plugslam {
inline namespace abi_v1 {

namespace {

struct VertexRecord {
  int64_t id;
  int line;
  std::array<double, 7> values;
};
struct EdgeRecord {
  int64_t from, to;
  int line;
  std::array<double, 28> values;  // measurement then information entries (g2o's order)
  // A TORO EDGE2: values[3..8] hold the information as the file wrote it, in an order decided
  // once the whole file is read (see resolveEdge2Order).
  bool edge2 = false;
};

class LineParser {
 public:
  LineParser(const std::string& file, int line, const std::string& text)
      : file_(file), line_(line), text_(text) {}

  bool next(std::string& token) {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    if (pos_ >= text_.size()) return false;
    const size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    token.assign(text_, start, pos_ - start);
    return true;
  }
  int64_t id(const char* what) {
    std::string t;
    if (!next(t)) fail(std::string("expected ") + what + " (an integer id), found end of line");
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(t.c_str(), &end, 10);
    if (end == t.c_str() || *end != '\0')
      fail(std::string("expected ") + what + " (an integer id), found '" + t + "'");
    if (errno == ERANGE) fail(std::string(what) + " '" + t + "' is out of range");
    return v;
  }
  double number(const char* what, int index, int count) {
    // from_chars straight from the line: no token copy, no locale.
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    if (pos_ >= text_.size()) {
      fail(std::string("expected ") + std::to_string(count) + " numbers for " + what + ", found " +
           std::to_string(index) + " (truncated line?)");
    }
    const char* begin = text_.data() + pos_;
    const char* stop = text_.data() + text_.size();
    if (*begin == '+') ++begin;
    double v = 0.0;
    const auto res = std::from_chars(begin, stop, v);
    const bool ends = res.ptr == stop || std::isspace(static_cast<unsigned char>(*res.ptr));
    if (res.ec != std::errc() || !ends) {
      std::string t;
      next(t);
      if (res.ec == std::errc::result_out_of_range && ends) {
        fail(std::string("non-finite value '") + t + "' in " + what);
      }
      fail(std::string("expected a number in ") + what + ", found '" + t + "'");
    }
    pos_ = res.ptr - text_.data();
    if (!std::isfinite(v)) {
      fail(std::string("non-finite value '") + std::string(begin, res.ptr) + "' in " + what);
    }
    return v;
  }
  void end() {
    std::string t;
    if (next(t)) fail("unexpected extra value '" + t + "' at end of record");
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw ParseError(file_, line_, message);
  }

 private:
  const std::string& file_;
  int line_;
  const std::string& text_;
  size_t pos_ = 0;
};

bool looksLikeTag(const std::string& t) {
  if (t.empty()) return false;
  for (char c : t) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == ':' || c == '-';
    if (!ok) return false;
  }
  return (t[0] >= 'A' && t[0] <= 'Z');
}

// Fills a symmetric n x n matrix from its upper triangle in row-major order.
template <int N>
Eigen::Matrix<double, N, N> upperToMatrix(const double* v) {
  Eigen::Matrix<double, N, N> m;
  int k = 0;
  for (int r = 0; r < N; ++r) {
    for (int c = r; c < N; ++c) {
      m(r, c) = m(c, r) = v[k++];
    }
  }
  return m;
}

// TORO/HOG-Man 3D rotation: roll, pitch, yaw about the fixed x, y, z axes, R = Rz Ry Rx.
Eigen::Quaterniond fromRollPitchYaw(double roll, double pitch, double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()));
}

// EDGE2 information, as written, into g2o's upper triangle (xx xy xt yy yt tt).
std::array<double, 6> edge2Information(const double* v, bool toro_order) {
  if (!toro_order) return {v[0], v[1], v[2], v[3], v[4], v[5]};
  return {v[0], v[1], v[4], v[2], v[5], v[3]};  // TORO: xx xy yy tt xt yt
}

template <int N>
bool isPositiveDefiniteFixed(const Eigen::Matrix<double, N, N>& m) {
  // Cholesky succeeds exactly for symmetric positive definite matrices.
  Eigen::LLT<Eigen::Matrix<double, N, N>> llt(m);
  return llt.info() == Eigen::Success && llt.matrixLLT().diagonal().minCoeff() > 0.0;
}

// EDGE2 information is TORO's order (xx xy yy tt xt yt), but some writers (GTSAM's w20000.txt)
// use g2o's (xx xy xt yy yt tt) under the same tag. When every EDGE2 matrix is positive definite
// in g2o's order and some is not in TORO's, the file is read in g2o's order (said once);
// otherwise in TORO's, and matrices that are not positive definite stay counted as before.
void resolveEdge2Order(const std::string& name, std::vector<EdgeRecord>& edges,
                       GraphFileInfo& info) {
  size_t count = 0, toro_pd = 0, g2o_pd = 0;
  for (const auto& e : edges) {
    if (!e.edge2) continue;
    ++count;
    const std::array<double, 6> t = edge2Information(e.values.data() + 3, true);
    const std::array<double, 6> g = edge2Information(e.values.data() + 3, false);
    toro_pd += isPositiveDefiniteFixed<3>(upperToMatrix<3>(t.data()));
    g2o_pd += isPositiveDefiniteFixed<3>(upperToMatrix<3>(g.data()));
  }
  if (count == 0) return;
  const bool toro_order = !(g2o_pd == count && toro_pd < count);
  info.edge2_information_order = toro_order ? "toro" : "g2o";
  if (!toro_order) {
    spdlog::warn(
        "{}: EDGE2 information read in g2o's order (xx xy xt yy yt tt), not TORO's (xx xy yy tt "
        "xt yt): in TORO's order {} of {} edges are not positive definite, in g2o's none is",
        name, count - toro_pd, count);
  }
  for (auto& e : edges) {
    if (!e.edge2) continue;
    const std::array<double, 6> m = edge2Information(e.values.data() + 3, toro_order);
    std::copy(m.begin(), m.end(), e.values.begin() + 3);
  }
}

}  // namespace

bool isPositiveDefinite(const Eigen::MatrixXd& m) {
  Eigen::LLT<Eigen::MatrixXd> llt(m);
  if (llt.info() != Eigen::Success) return false;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(m, Eigen::EigenvaluesOnly);
  return es.eigenvalues().minCoeff() > 0.0;
}

Eigen::MatrixXd nearestPositiveDefinite(const Eigen::MatrixXd& m, double min_ratio) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (m + m.transpose()));
  Eigen::VectorXd ev = es.eigenvalues();
  const double floor =
      std::max(min_ratio * ev.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  for (int i = 0; i < ev.size(); ++i) ev[i] = std::max(ev[i], floor);
  return es.eigenvectors() * ev.asDiagonal() * es.eigenvectors().transpose();
}

GraphFileInfo readGraphFile(const std::string& path, FactorGraph& graph,
                            const ReadGraphOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open graph file '" + path + "'");
  return readGraph(in, path, graph, options);
}

GraphFileInfo readGraph(std::istream& in, const std::string& name, FactorGraph& graph,
                        const ReadGraphOptions& options) {
  if (graph.numVariables() != 0 || graph.numFactors() != 0) {
    throw InputError("readGraph needs an empty graph");
  }
  GraphFileInfo info;
  std::vector<VertexRecord> vertices;
  std::vector<EdgeRecord> edges;
  std::vector<std::pair<int64_t, int>> fixes;
  bool toro = false, g2o = false;
  int dim_line = 0;
  auto setDim = [&](int d, LineParser& p, int line) {
    if (info.dimension == 0) {
      info.dimension = d;
      dim_line = line;
    } else if (info.dimension != d) {
      p.fail("a " + std::to_string(d) + "D record in a " + std::to_string(info.dimension) +
             "D graph (first record of that kind at line " + std::to_string(dim_line) + ")");
    }
  };
  std::string text, tag;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    for (unsigned char c : text) {
      if (c < 0x20 && c != '\t') throw ParseError(name, line, "binary data in a text graph file");
    }
    LineParser p(name, line, text);
    if (!p.next(tag) || tag[0] == '#') continue;
    if (tag == "VERTEX_SE2" || tag == "VERTEX2" || tag == "VERTEX") {
      (tag == "VERTEX_SE2" ? g2o : toro) = true;
      setDim(2, p, line);
      VertexRecord v{p.id("vertex id"), line, {}};
      for (int k = 0; k < 3; ++k) v.values[k] = p.number(tag.c_str(), k, 3);
      p.end();
      vertices.push_back(std::move(v));
    } else if (tag == "VERTEX_SE3:QUAT") {
      g2o = true;
      setDim(3, p, line);
      VertexRecord v{p.id("vertex id"), line, {}};
      for (int k = 0; k < 7; ++k) v.values[k] = p.number(tag.c_str(), k, 7);
      p.end();
      const double qn = Eigen::Vector4d(v.values[3], v.values[4], v.values[5], v.values[6]).norm();
      if (qn < 1e-6) p.fail("quaternion of vertex " + std::to_string(v.id) + " has zero norm");
      vertices.push_back(std::move(v));
    } else if (tag == "VERTEX3") {
      // TORO / HOG-Man 3D: x y z roll pitch yaw.
      toro = true;
      setDim(3, p, line);
      VertexRecord v{p.id("vertex id"), line, {}};
      double r[6];
      for (int k = 0; k < 6; ++k) r[k] = p.number(tag.c_str(), k, 6);
      p.end();
      const Eigen::Quaterniond q = fromRollPitchYaw(r[3], r[4], r[5]);
      v.values = {r[0], r[1], r[2], q.x(), q.y(), q.z(), q.w()};
      vertices.push_back(std::move(v));
    } else if (tag == "EDGE_SE2" || tag == "EDGE2" || tag == "EDGE") {
      const bool is_toro = tag != "EDGE_SE2";
      (is_toro ? toro : g2o) = true;
      setDim(2, p, line);
      EdgeRecord e{p.id("first vertex id"), 0, line, {}, is_toro};
      e.to = p.id("second vertex id");
      for (int k = 0; k < 9; ++k) e.values[k] = p.number(tag.c_str(), k, 9);
      p.end();
      edges.push_back(std::move(e));
    } else if (tag == "EDGE3") {
      // TORO / HOG-Man 3D: x y z roll pitch yaw, then the information's upper triangle over the
      // error (x y z roll pitch yaw) of the measured relative pose.
      toro = true;
      setDim(3, p, line);
      EdgeRecord e{p.id("first vertex id"), 0, line, {}};
      e.to = p.id("second vertex id");
      double v[27];
      for (int k = 0; k < 27; ++k) v[k] = p.number(tag.c_str(), k, 27);
      p.end();
      const Eigen::Quaterniond q = fromRollPitchYaw(v[3], v[4], v[5]);
      const double m[7] = {v[0], v[1], v[2], q.x(), q.y(), q.z(), q.w()};
      std::copy(m, m + 7, e.values.begin());
      // The error's rotation part is the relative rotation's roll/pitch/yaw there, ours its
      // quaternion's vector part: at the solution (small rotations) angles = 2 q.vec, so each
      // information entry gains a factor 2 per rotation index (g2o's EDGE_SE3:QUAT convention).
      int k = 0;
      for (int r = 0; r < 6; ++r)
        for (int c = r; c < 6; ++c, ++k)
          e.values[7 + k] = v[6 + k] * (r >= 3 ? 2.0 : 1.0) * (c >= 3 ? 2.0 : 1.0);
      edges.push_back(std::move(e));
    } else if (tag == "EDGE_SE3:QUAT") {
      g2o = true;
      setDim(3, p, line);
      EdgeRecord e{p.id("first vertex id"), 0, line, {}};
      e.to = p.id("second vertex id");
      for (int k = 0; k < 28; ++k) e.values[k] = p.number(tag.c_str(), k, 28);
      p.end();
      const double qn = Eigen::Vector4d(e.values[3], e.values[4], e.values[5], e.values[6]).norm();
      if (qn < 1e-6) p.fail("edge quaternion has zero norm");
      edges.push_back(std::move(e));
    } else if (tag == "FIX") {
      int64_t id = p.id("vertex id to fix");
      fixes.emplace_back(id, line);
      std::string more;
      while (p.next(more)) {
        LineParser q(name, line, more);
        fixes.emplace_back(q.id("vertex id to fix"), line);
      }
    } else if (looksLikeTag(tag)) {
      ++info.skipped_records;
    } else {
      throw ParseError(name, line,
                       "unknown record '" + tag.substr(0, 40) +
                           "'; expected VERTEX_SE2, EDGE_SE2, VERTEX_SE3:QUAT, "
                           "EDGE_SE3:QUAT, FIX, VERTEX2, EDGE2, VERTEX3 or EDGE3");
    }
  }
  if (in.bad()) throw ParseError(name, line, "read error");
  if (edges.empty() && vertices.empty()) {
    throw ParseError(name, 0, "no vertex or edge records found");
  }
  info.format = toro && !g2o ? "toro" : "g2o";
  resolveEdge2Order(name, edges, info);
  info.vertices = vertices.size();
  info.edges = edges.size();
  info.has_vertices = !vertices.empty();
  const int d = info.dimension;

  for (const auto& v : vertices) {
    if (graph.findVariable(v.id)) {
      throw ParseError(name, v.line, "duplicate vertex id " + std::to_string(v.id));
    }
    if (d == 2) {
      graph.addVariable<VariableSE2>(v.id, se2(v.values[0], v.values[1], v.values[2]));
    } else {
      graph.addVariable<VariableSE3>(
          v.id, se3(Eigen::Vector3d(v.values[0], v.values[1], v.values[2]),
                    Eigen::Quaterniond(v.values[6], v.values[3], v.values[4], v.values[5])));
    }
  }
  if (vertices.empty()) {
    // Edge-only file: one identity estimate per id, in id order (the odometry chain order),
    // set properly by the initialisation that follows.
    std::vector<int64_t> ids;
    for (const auto& e : edges) {
      ids.push_back(e.from);
      ids.push_back(e.to);
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    for (int64_t id : ids) {
      if (d == 2) {
        graph.addVariable<VariableSE2>(id, SE2::Identity());
      } else {
        graph.addVariable<VariableSE3>(id, SE3::Identity());
      }
    }
  }
  for (const auto& e : edges) {
    Variable* a = graph.findVariable(e.from);
    Variable* b = graph.findVariable(e.to);
    if (!a || !b) {
      throw ParseError(name, e.line,
                       "edge refers to vertex " + std::to_string(!a ? e.from : e.to) +
                           ", which the file does not declare");
    }
    if (a == b)
      throw ParseError(name, e.line, "edge from vertex " + std::to_string(e.from) + " to itself");
    const double* v = e.values.data();
    if (d == 2) {
      Eigen::Matrix3d inf = upperToMatrix<3>(v + 3);
      if (!isPositiveDefiniteFixed<3>(inf)) {
        ++info.non_pd_information;
        if (options.project_information) {
          inf = nearestPositiveDefinite(inf);
          ++info.projected_information;
        }
      }
      graph.emplaceFactor<BetweenFactorSE2>(
          static_cast<VariableSE2*>(a), static_cast<VariableSE2*>(b), se2(v[0], v[1], v[2]), inf);
    } else {
      Eigen::Matrix<double, 6, 6> inf = upperToMatrix<6>(v + 7);
      if (!isPositiveDefiniteFixed<6>(inf)) {
        ++info.non_pd_information;
        if (options.project_information) {
          inf = nearestPositiveDefinite(inf);
          ++info.projected_information;
        }
      }
      graph.emplaceFactor<BetweenFactorSE3>(
          static_cast<VariableSE3*>(a), static_cast<VariableSE3*>(b),
          se3(Eigen::Vector3d(v[0], v[1], v[2]), Eigen::Quaterniond(v[6], v[3], v[4], v[5])), inf);
    }
  }
  for (const auto& [id, fline] : fixes) {
    Variable* v = graph.findVariable(id);
    if (!v)
      throw ParseError(name, fline,
                       "FIX of vertex " + std::to_string(id) + ", which does not exist");
    if (!v->fixed()) ++info.fixed;
    v->setFixed(true);
  }
  return info;
}

namespace {
// Appends to a string: much cheaper than formatted stream output per number.
class TextBuffer {
 public:
  TextBuffer& operator<<(const char* s) {
    text_ += s;
    return *this;
  }
  TextBuffer& operator<<(char c) {
    text_ += c;
    return *this;
  }
  TextBuffer& operator<<(int64_t v) {
    char buf[24];
    const auto res = std::to_chars(buf, buf + sizeof(buf), v);
    text_.append(buf, res.ptr - buf);
    return *this;
  }
  std::string& text() { return text_; }

 private:
  std::string text_;
};
}  // namespace

size_t writeGraph(std::ostream& stream, const FactorGraph& graph) {
  TextBuffer out;
  out.text().reserve(64 * graph.numVariables() + 160 * graph.numFactors());
  auto num = [&](double x) {
    // Shortest representation that reads back to the same double.
    char buf[32];
    buf[0] = ' ';
    const auto res = std::to_chars(buf + 1, buf + sizeof(buf), x);
    out.text().append(buf, res.ptr - buf);
  };
  for (Variable* v : graph.variables()) {
    if (auto* p = dynamic_cast<VariableSE2*>(v)) {
      const Eigen::Vector3d x = toVector(p->estimate());
      out << "VERTEX_SE2 " << v->id();
      for (int k = 0; k < 3; ++k) num(x[k]);
      out << '\n';
    } else if (auto* p3 = dynamic_cast<VariableSE3*>(v)) {
      const Eigen::Vector3d t = p3->estimate().translation();
      const Eigen::Quaterniond q = quaternionOf(p3->estimate());
      out << "VERTEX_SE3:QUAT " << v->id();
      for (int k = 0; k < 3; ++k) num(t[k]);
      num(q.x());
      num(q.y());
      num(q.z());
      num(q.w());
      out << '\n';
    }
  }
  for (Variable* v : graph.variables()) {
    if (v->fixed()) out << "FIX " << v->id() << '\n';
  }
  size_t skipped = 0;
  for (const auto& f : graph.factors()) {
    if (auto* e = dynamic_cast<const BetweenFactorSE2*>(f.get())) {
      const Eigen::Vector3d m = toVector(e->measurement());
      out << "EDGE_SE2 " << e->variable(0)->id() << ' ' << e->variable(1)->id();
      for (int k = 0; k < 3; ++k) num(m[k]);
      for (int r = 0; r < 3; ++r)
        for (int c = r; c < 3; ++c) num(e->information()(r, c));
      out << '\n';
    } else if (auto* e3 = dynamic_cast<const BetweenFactorSE3*>(f.get())) {
      const Eigen::Vector3d t = e3->measurement().translation();
      const Eigen::Quaterniond q = quaternionOf(e3->measurement());
      out << "EDGE_SE3:QUAT " << e3->variable(0)->id() << ' ' << e3->variable(1)->id();
      for (int k = 0; k < 3; ++k) num(t[k]);
      num(q.x());
      num(q.y());
      num(q.z());
      num(q.w());
      for (int r = 0; r < 6; ++r)
        for (int c = r; c < 6; ++c) num(e3->information()(r, c));
      out << '\n';
    } else {
      ++skipped;
    }
  }
  stream.write(out.text().data(), std::streamsize(out.text().size()));
  return skipped;
}

size_t writeGraphFile(const std::string& path, const FactorGraph& graph) {
  size_t skipped = 0;
  writeFileAtomically(path, [&](std::ostream& out) { skipped = writeGraph(out, graph); });
  return skipped;
}

}  // namespace abi_v1
}  // namespace plugslam
