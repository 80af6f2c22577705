#include "rrr/solver/block_cholesky.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace rrr {

template <int D>
BlockCholesky<D>::BlockCholesky(
    int num_blocks, const std::vector<std::pair<int, int>>& off_diagonal)
    : num_blocks_(num_blocks),
      slot_by_col_(num_blocks),
      common_(std::make_unique<cholmod_common>()) {
  cholmod_start(common_.get());
  common_->supernodal = CHOLMOD_SUPERNODAL;
  common_->print = 0;

  // Upper-triangular block pattern, one slot per distinct pair.
  for (int b = 0; b < num_blocks; ++b) slot_by_col_[b].emplace_back(b, b);
  for (const auto& [a, b] : off_diagonal) {
    slot_by_col_[std::max(a, b)].emplace_back(std::min(a, b), -1);
  }
  int num_slots = 0;
  for (auto& col : slot_by_col_) {
    std::sort(col.begin(), col.end());
    col.erase(std::unique(col.begin(), col.end(),
                          [](const auto& x, const auto& y) {
                            return x.first == y.first;
                          }),
              col.end());
    num_slots += static_cast<int>(col.size());
  }
  slots_.resize(num_slots);
  // Diagonal blocks take slots 0..num_blocks-1, the rest follow.
  int next = num_blocks;
  for (int c = 0; c < num_blocks; ++c) {
    for (auto& [r, slot] : slot_by_col_[c]) slot = (r == c) ? c : next++;
  }

  const size_t n = static_cast<size_t>(num_blocks) * D;
  size_t nnz = 0;
  for (int c = 0; c < num_blocks; ++c) {
    nnz += (slot_by_col_[c].size() - 1) * D * D + D * (D + 1) / 2;
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
      for (const auto& [r, slot] : slot_by_col_[c]) {
        slots_[slot].row = r;
        slots_[slot].col = c;
        slots_[slot].start[k] = p;
        const int rows = (r == c) ? k + 1 : D;
        for (int a = 0; a < rows; ++a) rowind[p++] = r * D + a;
      }
    }
  }
  colptr[n] = p;
  // Analyse with a positive definite stand-in for the values.
  SetZero();
  for (int b = 0; b < num_blocks; ++b) AddDiagonal(b, Block::Identity());
  factor_ = cholmod_analyze(matrix_, common_.get());
  if (!factor_) throw std::runtime_error("CHOLMOD analysis failed");
}

template <int D>
BlockCholesky<D>::~BlockCholesky() {
  cholmod_free_factor(&factor_, common_.get());
  cholmod_free_sparse(&matrix_, common_.get());
  cholmod_finish(common_.get());
}

template <int D>
int BlockCholesky<D>::OffDiagonalSlot(int r, int c) const {
  const int row = std::min(r, c), col = std::max(r, c);
  const auto& entries = slot_by_col_.at(col);
  const auto it = std::lower_bound(entries.begin(), entries.end(),
                                   std::make_pair(row, -1));
  if (row == col || it == entries.end() || it->first != row) {
    throw std::out_of_range("block not in the sparsity pattern");
  }
  return it->second;
}

template <int D>
void BlockCholesky<D>::SetZero() {
  std::memset(matrix_->x, 0, sizeof(double) * matrix_->nzmax);
}

template <int D>
void BlockCholesky<D>::AddDiagonal(int block, const Block& m) {
  auto* x = static_cast<double*>(matrix_->x);
  const Slot& s = slots_[block];
  for (int k = 0; k < D; ++k) {
    for (int a = 0; a <= k; ++a) x[s.start[k] + a] += m(a, k);
  }
}

template <int D>
void BlockCholesky<D>::AddOffDiagonal(int slot, int r, int c, const Block& m) {
  auto* x = static_cast<double*>(matrix_->x);
  const Slot& s = slots_[slot];
  const bool transposed = r > c;
  for (int k = 0; k < D; ++k) {
    for (int a = 0; a < D; ++a) {
      x[s.start[k] + a] += transposed ? m(k, a) : m(a, k);
    }
  }
}

template <int D>
bool BlockCholesky<D>::Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x) {
  if (!cholmod_factorize(matrix_, factor_, common_.get()) ||
      common_->status == CHOLMOD_NOT_POSDEF) {
    return false;
  }
  cholmod_dense b;
  b.nrow = rhs.size();
  b.ncol = 1;
  b.nzmax = rhs.size();
  b.d = rhs.size();
  b.x = const_cast<double*>(rhs.data());
  b.z = nullptr;
  b.xtype = CHOLMOD_REAL;
  b.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* sol = cholmod_solve(CHOLMOD_A, factor_, &b, common_.get());
  if (!sol) return false;
  *x = Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(sol->x),
                                         rhs.size());
  cholmod_free_dense(&sol, common_.get());
  return x->allFinite();
}

template class BlockCholesky<3>;
template class BlockCholesky<6>;

}  // namespace rrr
