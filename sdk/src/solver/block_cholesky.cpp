#include "block_cholesky.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "plugslam/errors.h"

namespace plugslam {
namespace detail {

namespace {

// Symbolic structure shared by every block size.
struct Structure {
  int nb = 0;
  std::vector<int> perm, iperm;
  // The matrix, permuted upper block columns: rows a_row[a_ptr[k] .. a_ptr[k+1]) (sorted, the
  // diagonal last); block t's values start at t * B * B.
  std::vector<int> a_ptr, a_row;
  // L by block columns: l_ptr[i] is the diagonal block, then the rows below in increasing order.
  std::vector<int> l_ptr, l_row;
  // Row k of L below the diagonal, in the order the up-looking solve visits it: the block column
  // i and the position of block (k, i) in L.
  std::vector<int> r_ptr, r_col, r_pos;
};

class KernelBase {
 public:
  virtual ~KernelBase() = default;
  virtual void resize(const Structure& s) = 0;
  virtual bool factorize(const Structure& s, const double* a) = 0;
  virtual void solve(const Structure& s, const double* rhs, double* x) = 0;
};

template <int B>
class Kernel final : public KernelBase {
 public:
  using Block = Eigen::Matrix<double, B, B>;
  using Vec = Eigen::Matrix<double, B, 1>;
  using BlockMap = Eigen::Map<Block>;
  using ConstBlockMap = Eigen::Map<const Block>;
  using VecMap = Eigen::Map<Vec>;
  static constexpr int kBB = B * B;

  void resize(const Structure& s) override {
    l_.assign(s.l_row.size() * kBB, 0.0);
    l_inv_.assign(size_t(s.nb) * kBB, 0.0);
    work_.assign(size_t(s.nb) * kBB, 0.0);
    y_.assign(size_t(s.nb) * B, 0.0);
  }

  bool factorize(const Structure& s, const double* a) override {
    double* work = work_.data();
    for (int k = 0; k < s.nb; ++k) {
      const int diag = s.a_ptr[k + 1] - 1;
      for (int t = s.a_ptr[k]; t < diag; ++t) {
        BlockMap(work + size_t(s.a_row[t]) * kBB) = ConstBlockMap(a + size_t(t) * kBB);
      }
      Block d = ConstBlockMap(a + size_t(diag) * kBB);
      for (int t = s.r_ptr[k]; t < s.r_ptr[k + 1]; ++t) {
        const int i = s.r_col[t];
        const int pos = s.r_pos[t];
        BlockMap xi(work + size_t(i) * kBB);
        const Block y = ConstBlockMap(l_inv_.data() + size_t(i) * kBB) * xi;
        xi.setZero();
        for (int p = s.l_ptr[i] + 1; p < pos; ++p) {
          BlockMap(work + size_t(s.l_row[p]) * kBB).noalias() -=
              ConstBlockMap(l_.data() + size_t(p) * kBB) * y;
        }
        d.noalias() -= y.transpose() * y;
        BlockMap(l_.data() + size_t(pos) * kBB) = y.transpose();
      }
      // The diagonal block is stored full; only its upper triangle is read, as CHOLMOD does.
      Block lkk, inv;
      if (!choleskyAndInverse(d, lkk, inv)) return false;
      BlockMap(l_.data() + size_t(s.l_ptr[k]) * kBB) = lkk;
      BlockMap(l_inv_.data() + size_t(k) * kBB) = inv;
    }
    return true;
  }

  // Lower Cholesky factor of the symmetric d (upper triangle read) and its inverse, unrolled for
  // the fixed size (Eigen's LLT and triangular solve go through dynamic-size kernels here).
  // False unless d is positive definite with finite entries.
  static bool choleskyAndInverse(const Block& d, Block& l, Block& inv) {
    l.setZero();
    for (int j = 0; j < B; ++j) {
      double djj = d(j, j);
      for (int k = 0; k < j; ++k) djj -= l(j, k) * l(j, k);
      if (!(djj > 0.0) || !std::isfinite(djj)) return false;
      const double ljj = std::sqrt(djj);
      l(j, j) = ljj;
      for (int i = j + 1; i < B; ++i) {
        double v = d(j, i);
        for (int k = 0; k < j; ++k) v -= l(i, k) * l(j, k);
        l(i, j) = v / ljj;
      }
    }
    inv.setZero();
    for (int j = 0; j < B; ++j) {
      inv(j, j) = 1.0 / l(j, j);
      for (int i = j + 1; i < B; ++i) {
        double v = 0.0;
        for (int k = j; k < i; ++k) v -= l(i, k) * inv(k, j);
        inv(i, j) = v / l(i, i);
      }
    }
    return inv.allFinite();
  }

  void solve(const Structure& s, const double* rhs, double* x) override {
    double* y = y_.data();
    for (int k = 0; k < s.nb; ++k) {
      VecMap(y + size_t(k) * B) = Eigen::Map<const Vec>(rhs + size_t(s.perm[k]) * B);
    }
    for (int j = 0; j < s.nb; ++j) {
      VecMap yj(y + size_t(j) * B);
      yj = ConstBlockMap(l_inv_.data() + size_t(j) * kBB) * Vec(yj);
      for (int p = s.l_ptr[j] + 1; p < s.l_ptr[j + 1]; ++p) {
        VecMap(y + size_t(s.l_row[p]) * B).noalias() -=
            ConstBlockMap(l_.data() + size_t(p) * kBB) * yj;
      }
    }
    for (int j = s.nb - 1; j >= 0; --j) {
      Vec acc = VecMap(y + size_t(j) * B);
      for (int p = s.l_ptr[j] + 1; p < s.l_ptr[j + 1]; ++p) {
        acc.noalias() -= ConstBlockMap(l_.data() + size_t(p) * kBB).transpose() *
                         VecMap(y + size_t(s.l_row[p]) * B);
      }
      VecMap(y + size_t(j) * B) = ConstBlockMap(l_inv_.data() + size_t(j) * kBB).transpose() * acc;
    }
    for (int k = 0; k < s.nb; ++k) {
      Eigen::Map<Vec>(x + size_t(s.perm[k]) * B) = VecMap(y + size_t(k) * B);
    }
  }

 private:
  std::vector<double> l_, l_inv_, work_, y_;
};

std::unique_ptr<KernelBase> makeKernel(int block_dim) {
  switch (block_dim) {
    case 1:
      return std::make_unique<Kernel<1>>();
    case 2:
      return std::make_unique<Kernel<2>>();
    case 3:
      return std::make_unique<Kernel<3>>();
    case 6:
      return std::make_unique<Kernel<6>>();
    default:
      return nullptr;
  }
}

}  // namespace

struct BlockCholesky::Impl {
  int block_dim = 0;
  Structure s;
  std::vector<double> values;
  std::unique_ptr<KernelBase> kernel;
};

bool BlockCholesky::supportsBlockSize(int block_dim) {
  return block_dim == 1 || block_dim == 2 || block_dim == 3 || block_dim == 6;
}

BlockCholesky::BlockCholesky() : impl_(std::make_unique<Impl>()) {}
BlockCholesky::~BlockCholesky() = default;

namespace {

// The permuted upper block pattern (a_ptr, a_row) of `above` under perm, and its elimination
// tree (parent[k] = -1 at roots).
void permutedPatternAndTree(const std::vector<std::vector<int>>& above,
                            const std::vector<int>& perm, Structure& s, std::vector<int>& parent) {
  const int nb = int(above.size());
  s.nb = nb;
  s.perm = perm;
  s.iperm.assign(nb, 0);
  for (int k = 0; k < nb; ++k) s.iperm[perm[k]] = k;

  // Permuted upper pattern: original (r, c) lands in column max(P r, P c).
  std::vector<int> count(nb + 1, 0);
  for (int c = 0; c < nb; ++c) {
    for (int r : above[c]) ++count[std::max(s.iperm[r], s.iperm[c]) + 1];
    ++count[s.iperm[c] + 1];
  }
  s.a_ptr.assign(nb + 1, 0);
  for (int k = 0; k < nb; ++k) s.a_ptr[k + 1] = s.a_ptr[k] + count[k + 1];
  s.a_row.assign(s.a_ptr[nb], 0);
  std::vector<int> next(s.a_ptr.begin(), s.a_ptr.end() - 1);
  for (int c = 0; c < nb; ++c) {
    const int pc = s.iperm[c];
    for (int r : above[c]) {
      const int pr = s.iperm[r];
      s.a_row[next[std::max(pr, pc)]++] = std::min(pr, pc);
    }
    s.a_row[next[pc]++] = pc;
  }
  for (int k = 0; k < nb; ++k) {
    std::sort(s.a_row.begin() + s.a_ptr[k], s.a_row.begin() + s.a_ptr[k + 1]);
  }

  // Elimination tree (Liu's algorithm with path compression on the upper pattern).
  parent.assign(nb, -1);
  std::vector<int> ancestor(nb, -1);
  for (int k = 0; k < nb; ++k) {
    for (int t = s.a_ptr[k]; t < s.a_ptr[k + 1]; ++t) {
      for (int i = s.a_row[t]; i != -1 && i < k;) {
        const int up = ancestor[i];
        ancestor[i] = k;
        if (up == -1) parent[i] = k;
        i = up;
      }
    }
  }
}

}  // namespace

BlockCholesky::Fill BlockCholesky::predictFill(const std::vector<std::vector<int>>& above,
                                               const std::vector<int>& perm) {
  Structure s;
  std::vector<int> parent;
  permutedPatternAndTree(above, perm, s, parent);
  const int nb = s.nb;
  // Column counts of L from the row patterns (the ereach of each row), counted without storing
  // them: O(nnz(L)) time, O(n) memory, so a dense fill can be judged before it is allocated.
  std::vector<int> mark(nb, -1);
  std::vector<double> col_count(nb, 1.0);
  for (int k = 0; k < nb; ++k) {
    mark[k] = k;
    for (int t = s.a_ptr[k]; t < s.a_ptr[k + 1]; ++t) {
      for (int i = s.a_row[t]; mark[i] != k; i = parent[i]) {
        mark[i] = k;
        col_count[i] += 1.0;
      }
    }
  }
  Fill fill;
  fill.matrix_blocks = double(s.a_row.size());
  for (double c : col_count) {
    fill.factor_blocks += c;
    fill.block_flops += c * c;
  }
  return fill;
}

void BlockCholesky::analyze(int block_dim, const std::vector<std::vector<int>>& above,
                            const std::vector<int>& perm) {
  if (!supportsBlockSize(block_dim)) {
    throw InputError("block Cholesky: no kernel for blocks of size " + std::to_string(block_dim));
  }
  Impl& im = *impl_;
  Structure& s = im.s;
  std::vector<int> parent;
  permutedPatternAndTree(above, perm, s, parent);
  const int nb = s.nb;

  // Row patterns of L: the reach of each column's entries in the elimination tree, in
  // topological order (cs_ereach).
  std::vector<int> mark(nb, -1), stack(nb), path(nb);
  s.r_ptr.assign(nb + 1, 0);
  s.r_col.clear();
  for (int k = 0; k < nb; ++k) {
    int top = nb;
    mark[k] = k;
    for (int t = s.a_ptr[k]; t < s.a_ptr[k + 1]; ++t) {
      int len = 0;
      for (int i = s.a_row[t]; mark[i] != k; i = parent[i]) {
        path[len++] = i;
        mark[i] = k;
      }
      while (len > 0) stack[--top] = path[--len];
    }
    for (int t = top; t < nb; ++t) s.r_col.push_back(stack[t]);
    s.r_ptr[k + 1] = int(s.r_col.size());
  }

  // Column pointers of L and each row entry's position (columns fill in increasing row order).
  std::vector<int> col_count(nb, 1);
  for (int i : s.r_col) ++col_count[i];
  s.l_ptr.assign(nb + 1, 0);
  for (int i = 0; i < nb; ++i) s.l_ptr[i + 1] = s.l_ptr[i] + col_count[i];
  s.l_row.assign(s.l_ptr[nb], 0);
  std::vector<int> fill(nb);
  for (int i = 0; i < nb; ++i) {
    s.l_row[s.l_ptr[i]] = i;
    fill[i] = s.l_ptr[i] + 1;
  }
  s.r_pos.assign(s.r_col.size(), 0);
  for (int k = 0; k < nb; ++k) {
    for (int t = s.r_ptr[k]; t < s.r_ptr[k + 1]; ++t) {
      const int p = fill[s.r_col[t]]++;
      s.l_row[p] = k;
      s.r_pos[t] = p;
    }
  }

  im.block_dim = block_dim;
  im.values.assign(s.a_row.size() * size_t(block_dim) * block_dim, 0.0);
  im.kernel = makeKernel(block_dim);
  im.kernel->resize(s);
}

BlockCholesky::Location BlockCholesky::locate(int r, int c) const {
  const Structure& s = impl_->s;
  int pr = s.iperm[r], pc = s.iperm[c];
  Location loc;
  loc.transposed = pr > pc;
  if (loc.transposed) std::swap(pr, pc);
  const auto begin = s.a_row.begin() + s.a_ptr[pc];
  const auto end = s.a_row.begin() + s.a_ptr[pc + 1];
  const auto it = std::lower_bound(begin, end, pr);
  if (it == end || *it != pr) return Location{};
  loc.offset = int(it - s.a_row.begin()) * impl_->block_dim * impl_->block_dim;
  return loc;
}

double* BlockCholesky::values() { return impl_->values.data(); }

size_t BlockCholesky::numValues() const { return impl_->values.size(); }

bool BlockCholesky::factorize() {
  return impl_->kernel && impl_->kernel->factorize(impl_->s, impl_->values.data());
}

void BlockCholesky::solve(const double* rhs, double* x) { impl_->kernel->solve(impl_->s, rhs, x); }

}  // namespace detail
}  // namespace plugslam
