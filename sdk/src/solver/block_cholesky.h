#pragma once
// Sparse Cholesky over a matrix of equal-size dense blocks (one block per pose), used by the
// optimizer instead of CHOLMOD's scalar simplicial factorisation when every variable has the same
// dimension. CHOLMOD's simplicial LDL' pays index arithmetic per scalar; here it is paid per
// 3x3 / 6x6 block and the block products are fixed-size (unrolled) Eigen kernels.
#include <memory>
#include <vector>

namespace plugslam {
namespace detail {

/// Up-looking block LL' factorisation with a symbolic analysis computed once per pattern.
class BlockCholesky {
 public:
  /// Block sizes with a compiled kernel.
  static bool supportsBlockSize(int block_dim);

  /// Size of a factorisation, from the symbolic analysis.
  struct Fill {
    double matrix_blocks = 0.0;  ///< blocks in the upper triangle of the matrix (diagonal included)
    double factor_blocks = 0.0;  ///< blocks in L (diagonal included)
    double block_flops = 0.0;    ///< sum over block columns of L of (blocks in the column)^2
    /// Mean length of L's block columns weighted by their work (block_flops / factor_blocks):
    /// a few blocks on sparse (planar) graphs, hundreds when L fills in densely.
    double density() const { return factor_blocks > 0.0 ? block_flops / factor_blocks : 0.0; }
  };
  /// The fill of L under the ordering perm (same arguments as analyze), in O(nnz(L)) time and
  /// O(blocks) memory: decides between the block kernels and a supernodal factorisation before
  /// either allocates the factor.
  static Fill predictFill(const std::vector<std::vector<int>>& above, const std::vector<int>& perm);

  BlockCholesky();
  ~BlockCholesky();
  BlockCholesky(const BlockCholesky&) = delete;
  BlockCholesky& operator=(const BlockCholesky&) = delete;

  /// Symbolic analysis. above[c]: sorted block rows r < c with a nonzero block (r, c); every
  /// diagonal block is present. perm[k]: the original block eliminated k-th. block_dim must be
  /// supported.
  void analyze(int block_dim, const std::vector<std::vector<int>>& above,
               const std::vector<int>& perm);

  /// Where the matrix's upper block (r, c), r <= c in original numbering, is stored: column-major
  /// B x B at values() + offset. transposed: the stored block is the transpose of (r, c).
  struct Location {
    int offset = -1;          ///< first value of the stored block
    bool transposed = false;  ///< the stored block is (c, r)
  };
  /// Location of the upper block (r, c); both must be a pattern entry.
  Location locate(int r, int c) const;
  /// The matrix's values (all blocks, column-major B x B each); diagonal blocks are full.
  double* values();
  /// Number of values.
  size_t numValues() const;

  /// Numeric factorisation of the current values; false if not positive definite.
  bool factorize();
  /// Solves A x = rhs with the last successful factorisation (original numbering).
  void solve(const double* rhs, double* x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace detail
}  // namespace plugslam
