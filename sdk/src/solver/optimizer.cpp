#include "plugslam/solver/optimizer.h"

#include <cholmod.h>
#include <dlfcn.h>
#include <spdlog/spdlog.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "block_cholesky.h"
#include "core/enum_names.h"

namespace plugslam {
inline namespace abi_v1 {

// ABI 1.2 put `factorization` into the padding before `stats`: a 1.1 plugin's OptimizeResult
// (returned by value, so the caller allocates it) must keep its size (LP64: 80 bytes).
static_assert(sizeof(void*) != 8 || sizeof(OptimizeResult) == 80,
              "OptimizeResult changed size: plugins built against ABI 1.x would break");

namespace {
using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// With an optimised BLAS, kAuto leaves the block kernels for CHOLMOD's supernodal factorisation
// when L's block columns are this long on average (BlockCholesky::Fill::density). Measured with
// OpenBLAS 0.3.21, one thread (docs/benchmarks.md, History): block and supernodal tie at 91
// (a building's log replayed 10 times), supernodal wins 2.8x at 227 (20 times) and 3.5x at 615; the
// standard pose graphs stay at or below 43 (sphere2500), where the block kernels win 1.3-2.6x.
constexpr double kDenseFillDensity = 100.0;
}  // namespace

bool hasOptimizedBlas() {
  // Reference BLAS has no such symbol, and on it the block kernels beat supernodal at every
  // density measured, up to a fully dense factor (3x at density 1245).
  static const bool found = [] {
    for (const char* symbol :
         {"openblas_get_config", "MKL_Get_Version", "bli_info_get_version_str"}) {
      if (dlsym(RTLD_DEFAULT, symbol)) return true;
    }
    return false;
  }();
  return found;
}

namespace {
constexpr EnumName<Factorization> kFactorizationNames[] = {
    {Factorization::kSupernodal, "supernodal"},
    {Factorization::kSimplicial, "simplicial"},
    {Factorization::kAuto, "auto"},
    {Factorization::kBlock, "block"}};
constexpr EnumName<StopReason> kStopReasonNames[] = {
    {StopReason::kConverged, "converged"},
    {StopReason::kMaxIterations, "max_iterations"},
    {StopReason::kNoProgress, "no_progress"},
    {StopReason::kSolverFailure, "solver_failure"},
    {StopReason::kNothingToOptimize, "nothing_to_optimize"}};
}  // namespace

const char* toString(Factorization f) { return enumName(kFactorizationNames, f, "unknown"); }

const char* toString(StopReason r) { return enumName(kStopReasonNames, r, "unknown"); }

struct Optimizer::Impl {
  Impl() {
    cholmod_start(&common);
    common.print = 0;  // a non-positive-definite system is reported through OptimizeResult
  }
  ~Impl() {
    freeCholmod();
    cholmod_finish(&common);
  }

  void freeCholmod() {
    if (factor) cholmod_free_factor(&factor, &common);
    if (matrix) {
      matrix->x = nullptr;  // values belongs to Impl
      matrix->xtype = CHOLMOD_PATTERN;
      cholmod_free_sparse(&matrix, &common);
    }
    if (rhs) cholmod_free_dense(&rhs, &common);
    if (sol) cholmod_free_dense(&sol, &common);
    if (work_y) cholmod_free_dense(&work_y, &common);
    if (work_e) cholmod_free_dense(&work_e, &common);
  }

  // Structure of the current problem.
  std::vector<Variable*> active;  // free variables in system order
  std::vector<int> block_offset;  // scalar offset of each block
  std::vector<int> block_dim;
  std::vector<BlockSlot> slots;      // all factors' slots, concatenated
  std::vector<int> slot_start;       // per factor
  std::vector<int> b_offsets;        // all factors' variable offsets, concatenated
  std::vector<int> b_start;          // per factor
  std::vector<int> diag_pos;         // value index of each diagonal entry
  std::vector<int> block_of_scalar;  // block index of each scalar unknown
  std::vector<int> parent;           // gauge: union-find over variables
  std::vector<char> used, anchored, root_anchored;
  std::vector<double> diag_backup;
  int n = 0;
  bool dense = false;
  Factorization factorization = Factorization::kSupernodal;  // as requested
  Factorization cholmod_kind = Factorization::kAuto;         // CHOLMOD's kind for this structure
  Factorization analyzed_with = Factorization::kSupernodal;
  // Block path: every active variable has the same dimension and the block factorisation was
  // chosen; H lives in block's values instead of CHOLMOD's compressed columns.
  bool use_block = false;
  std::unique_ptr<detail::BlockCholesky> block;
  std::vector<std::vector<int>> block_above;  // pattern the block analysis was made for
  int block_analyzed_dim = 0;
  bool block_fill_checked = false;  // kAuto judged the analysed pattern's fill (kBlock does not)
  // kAuto found this pattern's fill too dense for the block kernels: CHOLMOD supernodal.
  std::vector<std::vector<int>> dense_fill_above;
  int dense_fill_dim = 0;

  // Sparse storage.
  std::vector<int> colptr, rowind;
  std::vector<double> values;
  cholmod_common common;
  cholmod_sparse* matrix = nullptr;
  cholmod_factor* factor = nullptr;
  cholmod_dense *rhs = nullptr, *sol = nullptr, *work_y = nullptr, *work_e = nullptr;

  // Dense storage.
  Eigen::MatrixXd hd;
  Eigen::LDLT<Eigen::MatrixXd, Eigen::Upper> ldlt;

  Eigen::VectorXd b, dx;

  void build(FactorGraph& graph, const OptimizerOptions& opt, OptimizeResult& result);
  void buildSparsePattern(const std::vector<std::vector<int>>& above);
  // Chooses the block path for this pattern (analysing it when it changed); false: use CHOLMOD.
  bool chooseBlockPath(const std::vector<std::vector<int>>& above);
  std::vector<int> blockOrdering(const std::vector<std::vector<int>>& above);
  // What solved the last system: kBlock, kSupernodal or kSimplicial (kAuto for the dense path).
  Factorization factorizationUsed() const;
  double linearize(const FactorGraph& graph);
  bool solve(double lambda);  // factorises H + lambda I and solves for dx
  bool backSolve();           // dx from the current b and the last factorisation
  bool has_factor = false;    // the last factorisation succeeded
};

void Optimizer::Impl::build(FactorGraph& graph, const OptimizerOptions& opt,
                            OptimizeResult& result) {
  const auto& factors = graph.factors();
  for (Variable* v : graph.variables()) v->setSystemOffset(-1);
  // Gauge: each connected component with neither a fixed variable nor a unary factor is fixed
  // at its first variable (graph order). Offsets temporarily hold graph indices; -3 marks an
  // implicitly fixed variable.
  const auto& vars = graph.variables();
  if (opt.gauge == GaugeMode::kAuto) {
    const int nv = int(vars.size());
    for (int k = 0; k < nv; ++k) vars[k]->setSystemOffset(k);
    parent.resize(nv);
    for (int k = 0; k < nv; ++k) parent[k] = k;
    auto find = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    used.assign(nv, 0);
    anchored.assign(nv, 0);
    for (const auto& f : factors) {
      const int m = f->numVariables();
      const int first = f->variable(0)->systemOffset();
      used[first] = 1;
      if (m == 1) anchored[first] = 1;
      for (int a = 1; a < m; ++a) {
        const int o = f->variable(a)->systemOffset();
        used[o] = 1;
        parent[find(o)] = find(first);
      }
    }
    root_anchored.assign(nv, 0);
    for (int k = 0; k < nv; ++k) {
      if (anchored[k] || vars[k]->fixed()) root_anchored[find(k)] = 1;
    }
    for (int k = 0; k < nv; ++k) vars[k]->setSystemOffset(-1);
    for (int k = 0; k < nv; ++k) {
      const int r = find(k);
      if (used[k] && !root_anchored[r]) {
        vars[k]->setSystemOffset(-3);
        root_anchored[r] = 1;
      }
    }
  }
  // Mark variables used by a factor (-2), then number them in graph order.
  for (const auto& f : factors) {
    for (int i = 0; i < f->numVariables(); ++i) {
      Variable* v = f->variable(i);
      if (!v->fixed() && v->systemOffset() != -3) v->setSystemOffset(-2);
    }
  }
  active.clear();
  block_offset.clear();
  block_dim.clear();
  n = 0;
  for (Variable* v : graph.variables()) {
    if (v->systemOffset() != -2) {
      v->setSystemOffset(-1);
      continue;
    }
    v->setSystemOffset(n);
    active.push_back(v);
    block_offset.push_back(n);
    block_dim.push_back(v->dim());
    n += v->dim();
  }
  result.system_size = n;
  dense = n <= opt.dense_threshold;
  result.dense = dense;
  block_of_scalar.resize(n);
  for (size_t k = 0; k < active.size(); ++k) {
    for (int j = 0; j < block_dim[k]; ++j) block_of_scalar[block_offset[k] + j] = int(k);
  }

  // Sparse pattern: block rows above the diagonal of each block column.
  std::vector<std::vector<int>> above;
  if (!dense) {
    above.assign(active.size(), {});
    for (const auto& f : factors) {
      const int m = f->numVariables();
      for (int a = 0; a < m; ++a) {
        const int oa = f->variable(a)->systemOffset();
        if (oa < 0) continue;
        for (int c = a + 1; c < m; ++c) {
          const int oc = f->variable(c)->systemOffset();
          if (oc < 0) continue;
          const int ba = block_of_scalar[oa], bc = block_of_scalar[oc];
          above[std::max(ba, bc)].push_back(std::min(ba, bc));
        }
      }
    }
    for (auto& col : above) {
      std::sort(col.begin(), col.end());
      col.erase(std::unique(col.begin(), col.end()), col.end());
    }
    use_block = chooseBlockPath(above);
    if (use_block) {
      diag_pos.resize(n);
      const int bd = block_dim.empty() ? 0 : block_dim[0];
      for (size_t k = 0; k < active.size(); ++k) {
        const int off = block->locate(int(k), int(k)).offset;
        for (int j = 0; j < bd; ++j) diag_pos[block_offset[k] + j] = off + j * bd + j;
      }
    } else {
      buildSparsePattern(above);
    }
  } else {
    use_block = false;
    if (hd.rows() != n) hd.resize(n, n);
    diag_pos.resize(n);
    for (int k = 0; k < n; ++k) diag_pos[k] = k * n + k;
  }
  diag_backup.resize(n);
  if (b.size() != n) {
    b.resize(n);
    dx.resize(n);
  }

  // Scatter slots of every factor.
  slots.clear();
  slot_start.clear();
  b_offsets.clear();
  b_start.clear();
  auto blockSlot = [&](int row_block, int col_block) {
    // Block (row_block <= col_block) of the upper triangle.
    BlockSlot s;
    if (use_block) {
      const detail::BlockCholesky::Location loc = block->locate(row_block, col_block);
      s.offset = loc.offset;
      s.stride = block_dim[col_block];
      s.transposed = loc.transposed;
      return s;
    }
    if (dense) {
      s.offset = block_offset[col_block] * n + block_offset[row_block];
      s.stride = n;
      return s;
    }
    const int c0 = block_offset[col_block];
    const int len = colptr[c0 + 1] - colptr[c0];
    int prefix = 0;
    if (row_block == col_block) {
      prefix = len - block_dim[col_block];
    } else {
      for (int r : above[col_block]) {
        if (r == row_block) break;
        prefix += block_dim[r];
      }
    }
    s.offset = colptr[c0] + prefix;
    s.stride = len;
    return s;
  };
  for (const auto& f : factors) {
    const int m = f->numVariables();
    slot_start.push_back(int(slots.size()));
    b_start.push_back(int(b_offsets.size()));
    for (int a = 0; a < m; ++a) {
      const int oa = f->variable(a)->systemOffset();
      b_offsets.push_back(oa);
      for (int c = a; c < m; ++c) {
        const int oc = f->variable(c)->systemOffset();
        if (oa < 0 || oc < 0) {
          slots.push_back(BlockSlot{});
          continue;
        }
        const int ba = block_of_scalar[oa], bc = block_of_scalar[oc];
        BlockSlot s = blockSlot(std::min(ba, bc), std::max(ba, bc));
        s.transposed = s.transposed != (ba > bc);
        slots.push_back(s);
      }
    }
  }
}

void Optimizer::Impl::buildSparsePattern(const std::vector<std::vector<int>>& above) {
  const int nb = int(above.size());
  std::vector<int> new_colptr, new_rowind;
  new_colptr.reserve(n + 1);
  new_colptr.push_back(0);
  for (int c = 0; c < nb; ++c) {
    for (int j = 0; j < block_dim[c]; ++j) {
      for (int r : above[c]) {
        for (int i = 0; i < block_dim[r]; ++i) new_rowind.push_back(block_offset[r] + i);
      }
      // Full diagonal block: CHOLMOD ignores the lower part (stype > 0) and the column stride
      // stays constant within the block column.
      for (int i = 0; i < block_dim[c]; ++i) new_rowind.push_back(block_offset[c] + i);
      new_colptr.push_back(int(new_rowind.size()));
    }
  }
  diag_pos.resize(n);
  for (int c = 0; c < nb; ++c) {
    for (int j = 0; j < block_dim[c]; ++j) {
      const int col = block_offset[c] + j;
      diag_pos[col] = new_colptr[col + 1] - block_dim[c] + j;
    }
  }
  const bool same =
      factor && new_colptr == colptr && new_rowind == rowind && analyzed_with == cholmod_kind;
  if (same) return;
  freeCholmod();
  colptr.swap(new_colptr);
  rowind.swap(new_rowind);
  const size_t nnz = rowind.size();
  values.assign(nnz, 0.0);
  matrix = cholmod_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_PATTERN, &common);
  std::copy(colptr.begin(), colptr.end(), static_cast<int*>(matrix->p));
  std::copy(rowind.begin(), rowind.end(), static_cast<int*>(matrix->i));
  matrix->x = values.data();  // values owns the numbers; detached again before free
  matrix->xtype = CHOLMOD_REAL;

  const std::vector<int> block_perm = blockOrdering(above);
  std::vector<int> perm;
  perm.reserve(n);
  for (int k = 0; k < nb; ++k) {
    const int blk = block_perm[k];
    for (int j = 0; j < block_dim[blk]; ++j) perm.push_back(block_offset[blk] + j);
  }
  common.supernodal = cholmod_kind == Factorization::kSupernodal   ? CHOLMOD_SUPERNODAL
                      : cholmod_kind == Factorization::kSimplicial ? CHOLMOD_SIMPLICIAL
                                                                   : CHOLMOD_AUTO;
  // Only the block ordering: by default CHOLMOD would also run AMD on the scalar matrix.
  common.nmethods = 1;
  common.method[0].ordering = CHOLMOD_GIVEN;
  factor = cholmod_analyze_p(matrix, perm.data(), nullptr, 0, &common);

  analyzed_with = cholmod_kind;
  rhs = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
}

std::vector<int> Optimizer::Impl::blockOrdering(const std::vector<std::vector<int>>& above) {
  // Fill-reducing ordering on the block graph (n_blocks nodes instead of n scalars).
  const int nb = int(above.size());
  std::vector<int> bp(nb + 1, 0), bi;
  for (int c = 0; c < nb; ++c) {
    for (int r : above[c]) bi.push_back(r);
    bi.push_back(c);
    bp[c + 1] = int(bi.size());
  }
  cholmod_sparse block_pattern{};
  block_pattern.nrow = nb;
  block_pattern.ncol = nb;
  block_pattern.nzmax = bi.size();
  block_pattern.p = bp.data();
  block_pattern.i = bi.data();
  block_pattern.stype = 1;
  block_pattern.itype = CHOLMOD_INT;
  block_pattern.xtype = CHOLMOD_PATTERN;
  block_pattern.dtype = CHOLMOD_DOUBLE;
  block_pattern.sorted = 1;
  block_pattern.packed = 1;
  std::vector<int> block_perm(nb);
  if (nb == 0 || !cholmod_amd(&block_pattern, nullptr, 0, block_perm.data(), &common)) {
    for (int k = 0; k < nb; ++k) block_perm[k] = k;
  }
  return block_perm;
}

bool Optimizer::Impl::chooseBlockPath(const std::vector<std::vector<int>>& above) {
  const bool automatic = factorization == Factorization::kAuto;
  cholmod_kind =
      automatic || factorization == Factorization::kBlock ? Factorization::kAuto : factorization;
  if (factorization != Factorization::kBlock && !automatic) return false;
  if (block_dim.empty()) return false;
  const int bd = block_dim[0];
  for (int d : block_dim) {
    if (d != bd) return false;
  }
  if (!detail::BlockCholesky::supportsBlockSize(bd)) return false;
  if (block && block_analyzed_dim == bd && block_above == above &&
      (!automatic || block_fill_checked)) {
    return true;
  }
  if (automatic && dense_fill_dim == bd && dense_fill_above == above) {
    cholmod_kind = Factorization::kSupernodal;
    return false;
  }
  const std::vector<int> perm = blockOrdering(above);
  if (automatic) {
    // Measured on the se-sync graphs (docs/benchmarks.md): the block kernels beat CHOLMOD's
    // simplicial path 3-4x on 2D graphs and its supernodal path 4x on sphere2500 (reference
    // BLAS). When L fills in densely (a building mapped over and over, every pass closing loops
    // with every other), an optimised BLAS-3 on CHOLMOD's dense supernodes wins; the reference
    // BLAS does not. Decided once per structure, before the factor is allocated.
    const detail::BlockCholesky::Fill fill = detail::BlockCholesky::predictFill(above, perm);
    const bool blas = hasOptimizedBlas();
    const bool dense_fill = blas && fill.density() > kDenseFillDensity;
    spdlog::debug(
        "optimizer: {} blocks of size {}, {:.0f} in H, {:.0f} in L, {:.3g} block flops, density "
        "{:.1f} (threshold {:.0f}, {} BLAS): {}",
        above.size(), bd, fill.matrix_blocks, fill.factor_blocks, fill.block_flops, fill.density(),
        kDenseFillDensity, blas ? "optimised" : "reference",
        dense_fill ? "CHOLMOD supernodal" : "block Cholesky");
    if (dense_fill) {
      dense_fill_above = above;
      dense_fill_dim = bd;
      block.reset();  // a block factor of another structure is not worth its memory any more
      block_above.clear();
      cholmod_kind = Factorization::kSupernodal;
      return false;
    }
  }
  if (!block) block = std::make_unique<detail::BlockCholesky>();
  block->analyze(bd, above, perm);
  block_above = above;
  block_analyzed_dim = bd;
  block_fill_checked = automatic;
  return true;
}

Factorization Optimizer::Impl::factorizationUsed() const {
  if (dense) return Factorization::kAuto;
  if (use_block) return Factorization::kBlock;
  return factor && factor->is_super ? Factorization::kSupernodal : Factorization::kSimplicial;
}

double Optimizer::Impl::linearize(const FactorGraph& graph) {
  double* h = dense ? hd.data() : use_block ? block->values() : values.data();
  if (dense) {
    hd.setZero();
  } else if (use_block) {
    std::fill(h, h + block->numValues(), 0.0);
  } else {
    std::fill(values.begin(), values.end(), 0.0);
  }
  b.setZero();
  const auto& factors = graph.factors();
  double cost = 0.0;
  for (size_t k = 0; k < factors.size(); ++k) {
    cost += factors[k]->linearize(h, b.data(), slots.data() + slot_start[k],
                                  b_offsets.data() + b_start[k]);
  }
  for (int k = 0; k < n; ++k) diag_backup[k] = h[diag_pos[k]];
  return cost;
}

bool Optimizer::Impl::solve(double lambda) {
  has_factor = false;
  double* h = dense ? hd.data() : use_block ? block->values() : values.data();
  for (int k = 0; k < n; ++k) h[diag_pos[k]] = diag_backup[k] + lambda;
  if (use_block) {
    if (!block->factorize()) return false;
  } else if (dense) {
    ldlt.compute(hd);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    const auto& d = ldlt.vectorD();
    if (!(d.minCoeff() > 1e-14 * std::max(1.0, d.maxCoeff()))) return false;
  } else {
    matrix->x = values.data();
    common.quick_return_if_not_posdef = 1;
    if (!cholmod_factorize(matrix, factor, &common)) return false;
    if (common.status == CHOLMOD_NOT_POSDEF || factor->minor < factor->n) return false;
  }
  has_factor = true;
  return backSolve();
}

bool Optimizer::Impl::backSolve() {
  if (!has_factor) return false;
  if (dense) {
    dx = ldlt.solve(-b);
  } else if (use_block) {
    dx = -b;
    block->solve(dx.data(), dx.data());
  } else {
    double* r = static_cast<double*>(rhs->x);
    for (int k = 0; k < n; ++k) r[k] = -b[k];
    if (!cholmod_solve2(CHOLMOD_A, factor, rhs, nullptr, &sol, nullptr, &work_y, &work_e,
                        &common)) {
      return false;
    }
    const double* x = static_cast<const double*>(sol->x);
    for (int k = 0; k < n; ++k) dx[k] = x[k];
  }
  return dx.allFinite();
}

Optimizer::Optimizer(const OptimizerOptions& options)
    : options_(options), impl_(std::make_unique<Impl>()) {}

Optimizer::~Optimizer() = default;

OptimizeResult Optimizer::optimize(FactorGraph& graph) {
  const auto t_start = Clock::now();
  OptimizeResult result;
  Impl& im = *impl_;
  const bool lm = options_.algorithm == Algorithm::kLevenbergMarquardt;
  im.factorization = options_.factorization;
  im.has_factor = false;
  im.build(graph, options_, result);
  result.factorization = im.factorizationUsed();
  result.time_setup = secondsSince(t_start);
  result.initial_chi2 = result.final_chi2 = graph.robustChi2();
  if (im.n == 0 || graph.numFactors() == 0) {
    result.reason = StopReason::kNothingToOptimize;
    result.time_total = secondsSince(t_start);
    return result;
  }

  double chi = result.initial_chi2;
  double lambda = 0.0, nu = 2.0;
  bool linearized_ahead = false;  // GN: H and b already hold the linearisation at the estimate
  double ahead_time = 0.0;
  result.reason = StopReason::kMaxIterations;
  // Reserved up front so that iterations do not allocate (the aligner calls this every frame).
  result.stats.reserve(std::min(options_.max_iterations, 64));
  for (int it = 0; it < options_.max_iterations; ++it) {
    IterationStats st;
    st.iteration = it;
    st.chi2_before = chi;
    auto t0 = Clock::now();
    if (linearized_ahead) {
      st.time_linearize = ahead_time;
      linearized_ahead = false;
    } else {
      im.linearize(graph);
      st.time_linearize = secondsSince(t0);
    }
    if (!lm && it > 0) {
      // Near a minimum H barely changes: the last factorisation predicts the next step's
      // decrease for the price of two triangular solves. Below the threshold, take that step
      // and stop without a new factorisation.
      t0 = Clock::now();
      const bool predicted_ok = im.backSolve();
      const double predicted = predicted_ok ? -im.b.dot(im.dx) : -1.0;
      st.time_solve += secondsSince(t0);
      if (predicted >= 0.0 && predicted < options_.relative_decrease * chi) {
        t0 = Clock::now();
        for (Variable* v : im.active) v->saveEstimate();
        for (Variable* v : im.active) v->oplus(im.dx.data() + v->systemOffset());
        const double new_chi = graph.robustChi2();
        if (std::isfinite(new_chi) && new_chi <= chi) {
          st.step_norm = im.dx.cwiseAbs().maxCoeff();
          chi = new_chi;
        } else {
          for (Variable* v : im.active) v->restoreEstimate();
        }
        st.time_update = secondsSince(t0);
        st.chi2 = chi;
        result.reason = StopReason::kConverged;
        result.iterations = it + 1;
        result.stats.push_back(st);
        if (callback_) callback_(st);
        break;
      }
    }
    if (lm && it == 0) {
      double max_diag = 0.0;
      for (double d : im.diag_backup) max_diag = std::max(max_diag, std::abs(d));
      lambda = options_.lm_initial_tau * std::max(max_diag, 1e-12);
    }
    bool done = false;
    // Ends the run with this iteration's step rejected.
    const auto stopRejected = [&](StopReason reason) {
      result.reason = reason;
      st.accepted = false;
      done = true;
    };
    // A step refused (no solution, or a cost not accepted): GN ends with the last good estimate;
    // LM raises its damping and tries again, until it has refused too many steps or refused one
    // below the step tolerance (`tiny`, converged). True when the run ends.
    const auto refuse = [&](bool tiny) {
      if (!lm) {
        stopRejected(StopReason::kSolverFailure);
        return true;
      }
      ++st.rejected_steps;
      lambda *= nu;
      nu *= 2.0;
      if (st.rejected_steps > options_.lm_max_rejections || tiny) {
        stopRejected(tiny ? StopReason::kConverged : StopReason::kNoProgress);
        return true;
      }
      return false;
    };
    for (;;) {
      t0 = Clock::now();
      const bool solved = im.solve(lm ? lambda : 0.0);
      st.time_solve += secondsSince(t0);
      t0 = Clock::now();
      if (!solved) {
        ++result.singular_systems;
        if (refuse(false)) break;
        continue;
      }
      for (Variable* v : im.active) v->saveEstimate();
      for (Variable* v : im.active) v->oplus(im.dx.data() + v->systemOffset());
      double new_chi;
      if (!lm) {
        // GN keeps every finite step, so the next linearisation can be done now: it yields the
        // new cost, which saves the separate evaluation.
        const auto tl = Clock::now();
        new_chi = im.linearize(graph);
        ahead_time = secondsSince(tl);
        linearized_ahead = std::isfinite(new_chi);
      } else {
        new_chi = graph.robustChi2();
      }
      const double step = im.dx.cwiseAbs().maxCoeff();
      bool accept = std::isfinite(new_chi);
      if (lm && accept) {
        const double predicted = im.dx.dot(lambda * im.dx - im.b);
        const double rho = (chi - new_chi) / predicted;
        accept = predicted > 0.0 && rho > 0.0;
        if (accept) {
          const double t = 2.0 * rho - 1.0;
          lambda *= std::max(1.0 / 3.0, 1.0 - t * t * t);
          nu = 2.0;
        }
      }
      st.time_update += secondsSince(t0) - (linearized_ahead ? ahead_time : 0.0);
      if (accept) {
        st.step_norm = step;
        st.lambda = lm ? lambda : 0.0;
        const double rel = (chi - new_chi) / std::max(chi, std::numeric_limits<double>::min());
        chi = new_chi;
        st.chi2 = chi;
        if (chi < options_.absolute_chi2 || (rel >= 0.0 && rel < options_.relative_decrease) ||
            step < options_.step_norm) {
          result.reason = StopReason::kConverged;
          done = true;
        }
        break;
      }
      for (Variable* v : im.active) v->restoreEstimate();
      // GN refuses a step only for a non-finite cost.
      if (refuse(step < options_.step_norm)) break;
    }
    if (!st.accepted) st.chi2 = chi;
    result.iterations = it + 1;
    result.stats.push_back(st);
    if (options_.verbose) {
      spdlog::info("iteration {} chi2 {:.6g} step {:.3g} lambda {:.3g} lin {:.4f}s solve {:.4f}s",
                   it, st.chi2, st.step_norm, st.lambda, st.time_linearize, st.time_solve);
    }
    if (callback_) callback_(st);
    if (done) break;
  }
  result.final_chi2 = chi;
  result.time_total = secondsSince(t_start);
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
