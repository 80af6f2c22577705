#include "rrr/solver/block_cholesky.h"

#include <algorithm>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace rrr {

namespace {

// Supernodal factors are factorized and solved with BLAS, which may not be
// safe to call from several threads at once (Debian's serial OpenBLAS is
// not: concurrent calls corrupt each other's results). Simplicial factors
// use no BLAS and need no lock.
std::mutex blas_mutex;

// Holds `blas_mutex` if `factor` is supernodal.
std::unique_lock<std::mutex> LockBlasFor(const cholmod_factor* factor) {
  return factor->is_super ? std::unique_lock<std::mutex>(blas_mutex)
                          : std::unique_lock<std::mutex>();
}

// The upper triangle, diagonal included, of the symmetric block pattern of
// `num_blocks` blocks with the off-diagonal pairs `pairs`: each column's rows
// ascending, without repeats.
BlockPattern UpperPattern(int num_blocks,
                          const std::vector<std::pair<int, int>>& pairs) {
  BlockPattern upper;
  upper.start.assign(num_blocks + 1, 0);
  for (int b = 0; b < num_blocks; ++b) ++upper.start[b + 1];
  for (const auto& [a, b] : pairs) ++upper.start[std::max(a, b) + 1];
  for (int c = 0; c < num_blocks; ++c) upper.start[c + 1] += upper.start[c];
  std::vector<int> fill(upper.start.begin(), upper.start.end() - 1);
  upper.row.resize(upper.start[num_blocks]);
  for (int b = 0; b < num_blocks; ++b) upper.row[fill[b]++] = b;
  for (const auto& [a, b] : pairs) {
    upper.row[fill[std::max(a, b)]++] = std::min(a, b);
  }
  // Each column sorted, repeats dropped, the columns closed up.
  int kept = 0;
  for (int c = 0; c < num_blocks; ++c) {
    const auto first = upper.row.begin() + upper.start[c];
    const auto last = upper.row.begin() + upper.start[c + 1];
    std::sort(first, last);
    const auto end = std::unique(first, last);
    const auto to = upper.row.begin() + kept;
    if (to != first) std::copy(first, end, to);  // to is before first
    upper.start[c] = kept;
    kept += static_cast<int>(end - first);
  }
  upper.start[num_blocks] = kept;
  upper.row.resize(kept);
  return upper;
}

// `upper` (an UpperPattern) with each block b renumbered place[b]: the
// UpperPattern of its off-diagonal entries so renumbered.
BlockPattern Renumbered(const BlockPattern& upper,
                        const std::vector<int>& place) {
  const int num_blocks = static_cast<int>(upper.start.size()) - 1;
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(upper.row.size() - num_blocks);
  for (int c = 0; c < num_blocks; ++c) {
    for (int e = upper.start[c]; e < upper.start[c + 1]; ++e) {
      if (upper.row[e] != c) pairs.emplace_back(place[upper.row[e]], place[c]);
    }
  }
  return UpperPattern(num_blocks, pairs);
}

// A fill-reducing ordering of a block pattern and the structure of its
// factor in that order.
struct BlockAnalysis {
  std::vector<int> position;  // position[block]: its place in the order
  std::vector<int> count;     // count[k]: block rows of the factor's column k
};

// Orders the block pattern `upper` (upper triangle with the diagonal) with
// CHOLMOD's default (AMD, postordered) and counts its factor's columns.
BlockAnalysis AnalyzeBlocks(const BlockPattern& upper, cholmod_common* common) {
  const size_t n = upper.start.size() - 1;
  cholmod_sparse* pattern = cholmod_allocate_sparse(
      n, n, upper.row.size(), 1, 1, /*stype=*/1, CHOLMOD_PATTERN, common);
  if (!pattern) throw std::runtime_error("CHOLMOD could not allocate pattern");
  std::copy(upper.start.begin(), upper.start.end(),
            static_cast<int*>(pattern->p));
  std::copy(upper.row.begin(), upper.row.end(), static_cast<int*>(pattern->i));
  // Only the ordering and the column counts are wanted, never a supernodal
  // structure of the block pattern.
  common->supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* symbolic = cholmod_analyze(pattern, common);
  if (!symbolic) throw std::runtime_error("CHOLMOD ordering failed");
  BlockAnalysis analysis{std::vector<int>(n), std::vector<int>(n)};
  const auto* perm = static_cast<const int*>(symbolic->Perm);
  const auto* count = static_cast<const int*>(symbolic->ColCount);
  for (size_t k = 0; k < n; ++k) {
    analysis.position[perm[k]] = static_cast<int>(k);
    analysis.count[k] = count[k];
  }
  cholmod_free_factor(&symbolic, common);
  cholmod_free_sparse(&pattern, common);
  return analysis;
}

}  // namespace

template <int D>
BlockCholesky<D>::BlockCholesky(
    int num_blocks, const std::vector<std::pair<int, int>>& off_diagonal)
    : num_blocks_(num_blocks), common_(std::make_unique<cholmod_common>()) {
  cholmod_start(common_.get());
  common_->print = 0;

  // Order the blocks once; the matrix is stored permuted, so every numeric
  // factorization runs in natural order without copying the matrix.
  const BlockPattern upper = UpperPattern(num_blocks, off_diagonal);
  const BlockAnalysis blocks = AnalyzeBlocks(upper, common_.get());
  position_ = blocks.position;
  stored_ = Renumbered(upper, position_);
  // Diagonal blocks take slots 0..num_blocks-1 (by permuted position), the
  // rest follow.
  slot_.resize(stored_.row.size());
  slots_.resize(stored_.row.size());
  int next = num_blocks;
  for (int c = 0; c < num_blocks; ++c) {
    for (int e = stored_.start[c]; e < stored_.start[c + 1]; ++e) {
      slot_[e] = stored_.row[e] == c ? c : next++;
    }
  }

  const size_t n = static_cast<size_t>(num_blocks) * D;
  size_t nnz = 0;
  for (int c = 0; c < num_blocks; ++c) {
    nnz +=
        (stored_.start[c + 1] - stored_.start[c] - 1) * D * D + D * (D + 1) / 2;
  }
  matrix_ = cholmod_allocate_sparse(n, n, nnz, /*sorted=*/1, /*packed=*/1,
                                    /*stype=*/1, CHOLMOD_REAL, common_.get());
  if (!matrix_) throw std::runtime_error("CHOLMOD could not allocate matrix");
  auto* colptr = static_cast<int*>(matrix_->p);
  auto* rowind = static_cast<int*>(matrix_->i);
  int p = 0;
  for (int c = 0; c < num_blocks; ++c) {
    for (int k = 0; k < D; ++k) {
      colptr[c * D + k] = p;
      for (int e = stored_.start[c]; e < stored_.start[c + 1]; ++e) {
        const int r = stored_.row[e];
        const int slot = slot_[e];
        slots_[slot].row = r;
        slots_[slot].col = c;
        slots_[slot].start[k] = p;
        const int rows = (r == c) ? k + 1 : D;
        for (int a = 0; a < rows; ++a) rowind[p++] = r * D + a;
      }
    }
  }
  colptr[n] = p;
  // Symbolic factorization in the stored (already reduced-fill) order. With
  // dense blocks the factor is block-dense on the block factor's pattern:
  // block column k of c block rows gives D scalar columns of D·(c − 1) + D − a
  // rows (a = 0 .. D − 1), the counts CHOLMOD's analysis of the scalar
  // pattern finds. They decide simplicial or supernodal as that analysis
  // does (flops Σ count² per nonzero Σ count); a simplicial factor needs
  // nothing more, so only a supernodal one is analysed again.
  common_->nmethods = 1;
  common_->method[0].ordering = CHOLMOD_NATURAL;
  common_->postorder = 0;
  // Most pose-graph factors have tiny supernodes, and Debian's supernodal
  // kernel enters OpenMP regions per supernode: simplicial unless the
  // factorization is heavy (flops / nnz(L) >= 200, e.g. dense 3D graphs),
  // where supernodal with BLAS wins ("Factorization", in the git history of
  // BENCHMARKS.md).
  common_->supernodal = CHOLMOD_AUTO;
  common_->supernodal_switch = 200;
  // Supernodes merged up to four times larger than CHOLMOD's defaults, which
  // count scalar columns and so merge little beyond a pose's own D: BLAS on
  // the larger ones runs faster than the explicit zeros they add cost (a
  // whole-map factorization of 48,865 2D junctions: 0.60 -> 0.45 s;
  // "Factorization", in the git history of BENCHMARKS.md).
  common_->nrelax[0] = 16;
  common_->nrelax[1] = 64;
  common_->nrelax[2] = 192;
  common_->zrelax[1] = 0.3;
  common_->zrelax[2] = 0.2;
  SetZero();
  for (int b = 0; b < num_blocks; ++b) SetDiagonal(b, Block::Identity());
  std::vector<int> count(n);
  double flops = 0.0, entries = 0.0;
  for (int k = 0; k < num_blocks; ++k) {
    for (int a = 0; a < D; ++a) {
      count[k * D + a] = D * (blocks.count[k] - 1) + D - a;
      flops += static_cast<double>(count[k * D + a]) * count[k * D + a];
      entries += count[k * D + a];
    }
  }
  if (entries > 0.0 && flops / entries >= common_->supernodal_switch) {
    factor_ = cholmod_analyze(matrix_, common_.get());
  } else {
    factor_ = cholmod_allocate_factor(n, common_.get());
    if (factor_) {
      std::copy(count.begin(), count.end(),
                static_cast<int*>(factor_->ColCount));
    }
  }
  if (!factor_) throw std::runtime_error("CHOLMOD analysis failed");
  rhs_ = Eigen::VectorXd(n);
}

template <int D>
BlockCholesky<D>::~BlockCholesky() {
  cholmod_free_factor(&factor_, common_.get());
  cholmod_free_sparse(&matrix_, common_.get());
  cholmod_finish(common_.get());
}

template <int D>
int BlockCholesky<D>::OffDiagonalSlot(int r, int c) const {
  const int pr = position_.at(r), pc = position_.at(c);
  const int row = std::min(pr, pc), col = std::max(pr, pc);
  const auto begin = stored_.row.begin() + stored_.start[col];
  const auto end = stored_.row.begin() + stored_.start[col + 1];
  const auto it = std::lower_bound(begin, end, row);
  if (row == col || it == end || *it != row) {
    throw std::out_of_range("block not in the sparsity pattern");
  }
  return slot_[it - stored_.row.begin()];
}

template <int D>
void BlockCholesky<D>::SetZero() {
  std::memset(matrix_->x, 0, sizeof(double) * matrix_->nzmax);
}

template <int D>
void BlockCholesky<D>::SetDiagonal(int block, const Block& m) {
  auto* x = static_cast<double*>(matrix_->x);
  const Slot& s = slots_[position_[block]];
  for (int k = 0; k < D; ++k) {
    for (int a = 0; a <= k; ++a) x[s.start[k] + a] = m(a, k);
  }
}

template <int D>
void BlockCholesky<D>::AddOffDiagonal(int slot, int r, int c, const Block& m) {
  auto* x = static_cast<double*>(matrix_->x);
  const Slot& s = slots_[slot];
  const bool transposed = position_[r] > position_[c];
  for (int k = 0; k < D; ++k) {
    for (int a = 0; a < D; ++a) {
      x[s.start[k] + a] += transposed ? m(k, a) : m(a, k);
    }
  }
}

template <int D>
bool BlockCholesky<D>::Factorize() {
  const std::unique_lock<std::mutex> lock = LockBlasFor(factor_);
  return cholmod_factorize(matrix_, factor_, common_.get()) &&
         common_->status != CHOLMOD_NOT_POSDEF;
}

namespace {

// A view of `values` as a one-column CHOLMOD dense matrix.
cholmod_dense DenseColumn(Eigen::VectorXd* values) {
  cholmod_dense dense;
  dense.nrow = values->size();
  dense.ncol = 1;
  dense.nzmax = values->size();
  dense.d = values->size();
  dense.x = values->data();
  dense.z = nullptr;
  dense.xtype = CHOLMOD_REAL;
  dense.dtype = CHOLMOD_DOUBLE;
  return dense;
}

}  // namespace

template <int D>
bool BlockCholesky<D>::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) {
  if (!Factorize()) return false;
  return SolveFactorized(rhs, x);
}

template <int D>
bool BlockCholesky<D>::SolveFactorized(const Eigen::VectorXd& rhs,
                                       Eigen::VectorXd* x) {
  const std::unique_lock<std::mutex> lock = LockBlasFor(factor_);
  for (int b = 0; b < num_blocks_; ++b) {
    rhs_.template segment<D>(position_[b] * D) = rhs.template segment<D>(b * D);
  }
  cholmod_dense dense = DenseColumn(&rhs_);
  cholmod_dense* sol = cholmod_solve(CHOLMOD_A, factor_, &dense, common_.get());
  if (!sol) return false;
  const auto* values = static_cast<const double*>(sol->x);
  x->resize(rhs.size());
  for (int b = 0; b < num_blocks_; ++b) {
    x->template segment<D>(b * D) =
        Eigen::Map<const Eigen::Matrix<double, D, 1>>(
            values + static_cast<std::ptrdiff_t>(position_[b]) * D);
  }
  cholmod_free_dense(&sol, common_.get());
  return x->allFinite();
}

template <int D>
Eigen::MatrixXd BlockCholesky<D>::InverseForm(const std::vector<int>& blocks,
                                              const Eigen::MatrixXd& b) {
  const int rows = static_cast<int>(blocks.size()) * D;
  // The rows of B, in the stored (permuted) order.
  std::vector<int> row(rows);
  for (size_t i = 0; i < blocks.size(); ++i) {
    for (int a = 0; a < D; ++a) row[i * D + a] = position_[blocks[i]] * D + a;
  }
  cholmod_sparse* set =
      cholmod_allocate_sparse(rhs_.size(), 1, rows, /*sorted=*/0,
                              /*packed=*/1, 0, CHOLMOD_PATTERN, common_.get());
  if (!set) throw std::runtime_error("CHOLMOD could not allocate a pattern");
  static_cast<int*>(set->p)[0] = 0;
  static_cast<int*>(set->p)[1] = rows;
  std::copy(row.begin(), row.end(), static_cast<int*>(set->i));
  // Bᵀ A⁻¹ B = (L⁻¹B)ᵀ D⁻¹ (L⁻¹B) for A = L D Lᵀ (D = I for L Lᵀ): each
  // column of L⁻¹B is nonzero only on the rows B's rows reach through the
  // elimination tree, the same for every column.
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
  cholmod_sparse* x_set = nullptr;
  rhs_.setZero();
  cholmod_dense column = DenseColumn(&rhs_);
  Eigen::MatrixXd reached;  // L⁻¹B on the rows reached
  Eigen::VectorXd pivots;   // D on those rows
  bool solved = true;
  {
    const std::unique_lock<std::mutex> lock = LockBlasFor(factor_);
    for (int j = 0; j < b.cols() && solved; ++j) {
      for (int r = 0; r < rows; ++r) rhs_[row[r]] = b(r, j);
      solved = cholmod_solve2(CHOLMOD_L, factor_, &column, set, &x, &x_set, &y,
                              &e, common_.get());
      if (!solved) break;
      const int reach = static_cast<int*>(x_set->p)[1];
      const auto* at = static_cast<const int*>(x_set->i);
      const auto* values = static_cast<const double*>(x->x);
      if (j == 0) {
        reached.resize(reach, b.cols());
        pivots.resize(reach);
        const auto* lp = static_cast<const int*>(factor_->p);
        const auto* lx = static_cast<const double*>(factor_->x);
        for (int k = 0; k < reach; ++k) {
          pivots[k] = factor_->is_ll ? 1.0 : lx[lp[at[k]]];
        }
      }
      solved = reach == reached.rows();  // one reach for every column
      for (int k = 0; k < reach && solved; ++k) reached(k, j) = values[at[k]];
    }
  }
  Eigen::MatrixXd form =
      solved ? Eigen::MatrixXd(reached.transpose() *
                               pivots.cwiseInverse().asDiagonal() * reached)
             : Eigen::MatrixXd();
  cholmod_free_dense(&x, common_.get());
  cholmod_free_dense(&y, common_.get());
  cholmod_free_dense(&e, common_.get());
  cholmod_free_sparse(&x_set, common_.get());
  cholmod_free_sparse(&set, common_.get());
  if (!solved) throw std::runtime_error("CHOLMOD sparse solve failed");
  return form;
}

template class BlockCholesky<3>;
template class BlockCholesky<6>;

}  // namespace rrr
