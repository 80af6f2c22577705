#include "rrr/solver/block_cholesky.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace rrr {
namespace {

// A system of `num_blocks` blocks whose off-diagonal pattern is `pairs`,
// filled as a least-squares problem fills it: each pair adds JᵀJ for a random
// J = [J_r J_c], and every diagonal block the identity. Solves it with
// BlockCholesky and returns the largest difference from a dense solve.
template <int D>
double LargestErrorOfSolve(int num_blocks,
                           const std::vector<std::pair<int, int>>& pairs,
                           std::mt19937* random) {
  using Block = typename BlockCholesky<D>::Block;
  std::normal_distribution<double> normal;
  const auto random_block = [&] {
    Block m;
    for (int i = 0; i < D * D; ++i) m.data()[i] = normal(*random);
    return m;
  };
  const int n = num_blocks * D;
  Eigen::MatrixXd dense = Eigen::MatrixXd::Identity(n, n);
  std::vector<Block> diagonal(num_blocks, Block::Identity());
  BlockCholesky<D> system(num_blocks, pairs);
  system.SetZero();
  for (const auto& [r, c] : pairs) {
    const Block jr = random_block(), jc = random_block();
    diagonal[r] += jr.transpose() * jr;
    diagonal[c] += jc.transpose() * jc;
    const Block off = jr.transpose() * jc;
    system.AddOffDiagonal(system.OffDiagonalSlot(r, c), r, c, off);
    dense.block<D, D>(r * D, r * D) += jr.transpose() * jr;
    dense.block<D, D>(c * D, c * D) += jc.transpose() * jc;
    dense.block<D, D>(r * D, c * D) += off;
    dense.block<D, D>(c * D, r * D) += off.transpose();
  }
  for (int b = 0; b < num_blocks; ++b) system.SetDiagonal(b, diagonal[b]);
  Eigen::VectorXd rhs(n);
  for (int i = 0; i < n; ++i) rhs[i] = normal(*random);
  Eigen::VectorXd x;
  EXPECT_TRUE(system.Solve(rhs, &x));
  const Eigen::VectorXd expected = dense.ldlt().solve(rhs);
  return (x - expected).cwiseAbs().maxCoeff() /
         std::max(1.0, expected.cwiseAbs().maxCoeff());
}

// `count` random pairs of distinct blocks, some repeated and in either order.
std::vector<std::pair<int, int>> RandomPairs(int num_blocks, int count,
                                             std::mt19937* random) {
  std::uniform_int_distribution<int> block(0, num_blocks - 1);
  std::vector<std::pair<int, int>> pairs;
  while (static_cast<int>(pairs.size()) < count) {
    const int a = block(*random), b = block(*random);
    if (a != b) pairs.emplace_back(a, b);
  }
  return pairs;
}

// Every pair of distinct blocks: a dense matrix, whose factorization is heavy
// enough for CHOLMOD's supernodal kernel.
std::vector<std::pair<int, int>> AllPairs(int num_blocks) {
  std::vector<std::pair<int, int>> pairs;
  for (int a = 0; a < num_blocks; ++a) {
    for (int b = a + 1; b < num_blocks; ++b) pairs.emplace_back(b, a);
  }
  return pairs;
}

TEST(BlockCholesky, SolvesSparseSystemsAsADenseSolveDoes) {
  std::mt19937 random(7);
  for (const int num_blocks : {1, 2, 5, 40, 150}) {
    for (const int per_block : {0, 1, 3}) {
      const int count = num_blocks > 1 ? per_block * num_blocks : 0;
      const auto pairs = RandomPairs(num_blocks, count, &random);
      EXPECT_LT(LargestErrorOfSolve<3>(num_blocks, pairs, &random), 1e-9)
          << num_blocks << " blocks, " << pairs.size() << " pairs";
      EXPECT_LT(LargestErrorOfSolve<6>(num_blocks, pairs, &random), 1e-9)
          << num_blocks << " blocks, " << pairs.size() << " pairs";
    }
  }
}

TEST(BlockCholesky, SolvesDenseSystemsAsADenseSolveDoes) {
  std::mt19937 random(11);
  EXPECT_LT(LargestErrorOfSolve<3>(120, AllPairs(120), &random), 1e-9);
  EXPECT_LT(LargestErrorOfSolve<6>(60, AllPairs(60), &random), 1e-9);
}

TEST(BlockCholesky, SolvesAgainAfterTheValuesChange) {
  std::mt19937 random(13);
  const auto pairs = RandomPairs(50, 100, &random);
  BlockCholesky<3> system(50, pairs);
  for (int round = 0; round < 2; ++round) {
    const double scale = 1.0 + round;
    system.SetZero();
    for (int b = 0; b < 50; ++b) {
      system.SetDiagonal(b, scale * BlockCholesky<3>::Block::Identity());
    }
    Eigen::VectorXd rhs = Eigen::VectorXd::Ones(150), x;
    ASSERT_TRUE(system.Solve(rhs, &x));
    EXPECT_NEAR(x.maxCoeff(), 1.0 / scale, 1e-12);
    EXPECT_NEAR(x.minCoeff(), 1.0 / scale, 1e-12);
  }
}

TEST(BlockCholesky, RefusesASingularMatrix) {
  BlockCholesky<3> system(3, {{0, 1}, {1, 2}});
  system.SetZero();
  for (int b = 0; b < 3; ++b) {
    system.SetDiagonal(b, BlockCholesky<3>::Block::Identity());
  }
  // Block 1 holds no information: a pose no edge constrains.
  system.SetDiagonal(1, BlockCholesky<3>::Block::Zero());
  Eigen::VectorXd x;
  EXPECT_FALSE(system.Solve(Eigen::VectorXd::Ones(9), &x));
}

TEST(BlockCholesky, IsBuiltForAProblemWithNothingFree) {
  const BlockCholesky<3> system(0, {});
  EXPECT_EQ(system.num_blocks(), 0);
  EXPECT_THROW(system.OffDiagonalSlot(0, 1), std::out_of_range);
}

TEST(BlockCholesky, NamesOnlyThePairsOfItsPattern) {
  const BlockCholesky<3> system(4, {{0, 1}, {3, 1}, {1, 0}});
  EXPECT_EQ(system.OffDiagonalSlot(0, 1), system.OffDiagonalSlot(1, 0));
  EXPECT_NE(system.OffDiagonalSlot(1, 3), system.OffDiagonalSlot(0, 1));
  EXPECT_THROW(system.OffDiagonalSlot(0, 3), std::out_of_range);
  EXPECT_THROW(system.OffDiagonalSlot(2, 2), std::out_of_range);
  EXPECT_THROW(system.OffDiagonalSlot(0, 4), std::out_of_range);
}

}  // namespace
}  // namespace rrr
