// A symmetric positive definite block-sparse system solved with CHOLMOD.
#ifndef RRR_SOLVER_BLOCK_CHOLESKY_H_
#define RRR_SOLVER_BLOCK_CHOLESKY_H_

#include <cholmod.h>

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

namespace rrr {

// A block pattern by column: the rows of column c are
// row[start[c] .. start[c + 1]), ascending and distinct.
struct BlockPattern {
  std::vector<int> start, row;
};

// The matrix has `num_blocks` × `num_blocks` blocks of size D × D: all
// diagonal blocks and the off-diagonal blocks given at construction. The
// sparsity pattern is analysed once, at construction: a fill-reducing block
// ordering, in which the matrix is then stored, and the symbolic
// factorization. Each Solve() only refactorizes numerically, in place. Blocks
// of the pattern that are left zero cost nothing extra in correctness, so one
// instance serves every subset of the pattern's edges.
template <int D>
class BlockCholesky {
 public:
  using Block = Eigen::Matrix<double, D, D>;

  // `off_diagonal` lists block pairs (r, c) with r != c; each unordered pair
  // may appear any number of times. Throws std::runtime_error if CHOLMOD fails.
  BlockCholesky(int num_blocks,
                const std::vector<std::pair<int, int>>& off_diagonal);
  ~BlockCholesky();
  BlockCholesky(const BlockCholesky&) = delete;
  BlockCholesky& operator=(const BlockCholesky&) = delete;

  int num_blocks() const { return num_blocks_; }
  // The slot of the off-diagonal block {r, c}, to be used with AddOffDiagonal.
  // Throws std::out_of_range if the pair is not in the pattern.
  int OffDiagonalSlot(int r, int c) const;

  // Clears every value (the pattern stays).
  void SetZero();
  // A(b, b) = m; m must be symmetric.
  void SetDiagonal(int block, const Block& m);
  // A(r, c) += m and A(c, r) += mᵀ for the slot of (r, c) in that order.
  void AddOffDiagonal(int slot, int r, int c, const Block& m);

  // Solves A x = rhs. Returns false if A is singular (a zero pivot) or, for
  // a supernodal factor, not positive definite. A simplicial factor is
  // LDLᵀ, which does not refuse an indefinite A: callers' matrices are
  // Gauss–Newton ones (JᵀΣ⁻¹J plus damping), never indefinite.
  bool Solve(const Eigen::VectorXd& rhs, Eigen::VectorXd* x);
  // As Solve, with the last successful Factorize().
  bool SolveFactorized(const Eigen::VectorXd& rhs, Eigen::VectorXd* x);

  // Factorizes A as it is now. Returns false as Solve does.
  bool Factorize();
  // Bᵀ A⁻¹ B at the last successful Factorize(), for B zero but in the
  // block rows `blocks` (distinct), where it is `b`: rows D·i .. D·i+D−1 of
  // `b` are B's block row blocks[i]. Each column costs a solve on the part
  // of the factor the column reaches, not on the whole (CHOLMOD's sparse
  // solve): cheap for a B of few blocks. Changes the factor to simplicial
  // form if it was supernodal (later factorizations stay simplicial).
  Eigen::MatrixXd InverseForm(const std::vector<int>& blocks,
                              const Eigen::MatrixXd& b);

 private:
  int num_blocks_;
  std::vector<int> position_;  // permuted position of each block
  // For each slot: permuted block row and column (row <= column) and, for each
  // of the D scalar columns, the index in A's values of the block's first row.
  struct Slot {
    int row, col;
    int start[D];
  };
  std::vector<Slot> slots_;  // slot p < num_blocks is diagonal position p
  // The stored upper block pattern (permuted numbering) and the slot of
  // each of its entries.
  BlockPattern stored_;
  std::vector<int> slot_;
  Eigen::VectorXd rhs_;  // right-hand side in permuted order
  std::unique_ptr<cholmod_common> common_;
  cholmod_sparse* matrix_ = nullptr;
  cholmod_factor* factor_ = nullptr;
};

}  // namespace rrr

#endif  // RRR_SOLVER_BLOCK_CHOLESKY_H_
