// The optimizer's block Cholesky (sdk/src/solver, internal) against a dense Eigen solve.
#include "block_cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <numeric>
#include <random>

#include "plugslam/errors.h"

using plugslam::detail::BlockCholesky;

namespace {

// A random symmetric block pattern (a chain plus random extra blocks, like a pose graph with
// loop closures) and a random elimination order.
struct Problem {
  int nb = 0, bd = 0;
  std::vector<std::vector<int>> above;
  std::vector<int> perm;
  Eigen::MatrixXd dense;  // the full matrix
};

Problem makeProblem(int nb, int bd, int extra, bool positive_definite, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick(0, nb - 1);
  std::normal_distribution<double> nd(0.0, 1.0);
  Problem p;
  p.nb = nb;
  p.bd = bd;
  p.above.assign(nb, {});
  for (int c = 1; c < nb; ++c) p.above[c].push_back(c - 1);
  for (int e = 0; e < extra; ++e) {
    const int a = pick(rng), b = pick(rng);
    if (a != b) p.above[std::max(a, b)].push_back(std::min(a, b));
  }
  for (auto& col : p.above) {
    std::sort(col.begin(), col.end());
    col.erase(std::unique(col.begin(), col.end()), col.end());
  }
  p.perm.resize(nb);
  std::iota(p.perm.begin(), p.perm.end(), 0);
  std::shuffle(p.perm.begin(), p.perm.end(), rng);
  // Sum of random rank-bd "edge" terms J'J per pattern block keeps the matrix PSD; a diagonal
  // shift makes it definite (or, with a negative shift, indefinite).
  const int n = nb * bd;
  p.dense = Eigen::MatrixXd::Zero(n, n);
  for (int c = 0; c < nb; ++c) {
    for (int r : p.above[c]) {
      Eigen::MatrixXd j(bd, n);
      j.setZero();
      for (int a = 0; a < bd; ++a) {
        for (int b = 0; b < bd; ++b) {
          j(a, r * bd + b) = nd(rng);
          j(a, c * bd + b) = nd(rng);
        }
      }
      p.dense += j.transpose() * j;
    }
  }
  p.dense.diagonal().array() += positive_definite ? 0.5 : -1e3;
  return p;
}

void fill(BlockCholesky& chol, const Problem& p) {
  std::fill(chol.values(), chol.values() + chol.numValues(), 0.0);
  auto put = [&](int r, int c) {
    const BlockCholesky::Location loc = chol.locate(r, c);
    ASSERT_GE(loc.offset, 0) << r << "," << c;
    Eigen::Map<Eigen::MatrixXd> blk(chol.values() + loc.offset, p.bd, p.bd);
    const Eigen::MatrixXd src = p.dense.block(r * p.bd, c * p.bd, p.bd, p.bd);
    if (loc.transposed) {
      blk = src.transpose();
    } else {
      blk = src;
    }
  };
  for (int c = 0; c < p.nb; ++c) {
    for (int r : p.above[c]) put(r, c);
    put(c, c);
  }
}

}  // namespace

TEST(BlockCholesky, SolvesLikeDenseForEveryBlockSize) {
  for (int bd : {1, 2, 3, 6}) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const Problem p = makeProblem(60, bd, 40, true, seed * 17 + bd);
      BlockCholesky chol;
      chol.analyze(bd, p.above, p.perm);
      fill(chol, p);
      ASSERT_TRUE(chol.factorize()) << "bd " << bd << " seed " << seed;
      std::mt19937 rng(seed);
      std::normal_distribution<double> nd(0.0, 1.0);
      Eigen::VectorXd rhs(p.nb * bd);
      for (int k = 0; k < rhs.size(); ++k) rhs[k] = nd(rng);
      Eigen::VectorXd x(rhs.size());
      chol.solve(rhs.data(), x.data());
      const Eigen::VectorXd expected = p.dense.llt().solve(rhs);
      EXPECT_LT((x - expected).norm(), 1e-9 * (1.0 + expected.norm())) << "bd " << bd;
      // In place, as the optimizer calls it.
      Eigen::VectorXd y = rhs;
      chol.solve(y.data(), y.data());
      EXPECT_LT((y - expected).norm(), 1e-9 * (1.0 + expected.norm()));
    }
  }
}

TEST(BlockCholesky, RefactorizesNewValuesOnTheSameAnalysis) {
  const Problem a = makeProblem(40, 3, 30, true, 5);
  Problem b = a;
  b.dense.diagonal().array() += 10.0;
  BlockCholesky chol;
  chol.analyze(3, a.above, a.perm);
  const Eigen::VectorXd rhs = Eigen::VectorXd::LinSpaced(a.nb * 3, -1.0, 1.0);
  for (const Problem* p : std::vector<const Problem*>{&a, &b, &a}) {
    fill(chol, *p);
    ASSERT_TRUE(chol.factorize());
    Eigen::VectorXd x(rhs.size());
    chol.solve(rhs.data(), x.data());
    EXPECT_LT((p->dense * x - rhs).norm(), 1e-9);
  }
}

TEST(BlockCholesky, IndefiniteMatrixIsRefused) {
  const Problem p = makeProblem(30, 3, 20, false, 9);
  BlockCholesky chol;
  chol.analyze(3, p.above, p.perm);
  fill(chol, p);
  EXPECT_FALSE(chol.factorize());
}

TEST(BlockCholesky, UnsupportedBlockSizeIsAnInputError) {
  BlockCholesky chol;
  EXPECT_THROW(chol.analyze(5, {{}, {0}}, {0, 1}), plugslam::InputError);
  EXPECT_FALSE(BlockCholesky::supportsBlockSize(5));
}

TEST(BlockCholesky, PredictFillOfAChainAndOfAFullPattern) {
  const int nb = 50;
  std::vector<int> identity(nb);
  std::iota(identity.begin(), identity.end(), 0);
  // A chain in its natural order does not fill in: L has the diagonal and one block below it.
  std::vector<std::vector<int>> chain(nb);
  for (int c = 1; c < nb; ++c) chain[c] = {c - 1};
  const BlockCholesky::Fill fc = BlockCholesky::predictFill(chain, identity);
  EXPECT_EQ(fc.matrix_blocks, 2 * nb - 1);
  EXPECT_EQ(fc.factor_blocks, 2 * nb - 1);
  EXPECT_EQ(fc.block_flops, 4.0 * (nb - 1) + 1.0);
  EXPECT_LT(fc.density(), 2.0);
  // Reversed, every column c keeps one block below it too: the chain has no fill either way.
  std::vector<int> reversed(identity.rbegin(), identity.rend());
  EXPECT_EQ(BlockCholesky::predictFill(chain, reversed).factor_blocks, 2 * nb - 1);
  // An arrow pointing at the first block, eliminated first, fills L completely.
  std::vector<std::vector<int>> arrow(nb);
  for (int c = 1; c < nb; ++c) arrow[c] = {0};
  const BlockCholesky::Fill fa = BlockCholesky::predictFill(arrow, identity);
  EXPECT_EQ(fa.matrix_blocks, 2 * nb - 1);
  EXPECT_EQ(fa.factor_blocks, nb * (nb + 1) / 2);
  double flops = 0.0;
  for (int k = 1; k <= nb; ++k) flops += double(k) * k;
  EXPECT_EQ(fa.block_flops, flops);
  EXPECT_NEAR(fa.density(), (2.0 * nb + 1.0) / 3.0, 1e-9);
  // Eliminated last, the hub costs nothing: one block below every other diagonal.
  EXPECT_EQ(BlockCholesky::predictFill(arrow, reversed).factor_blocks, 2 * nb - 1);
}
