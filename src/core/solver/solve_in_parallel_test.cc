#include "rrr/solver/solve_in_parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <numeric>
#include <stdexcept>
#include <vector>

namespace rrr {
namespace {

// Errors that name the subset: the loop errors are the loop indices and the
// total is their sum. Throws for a subset holding a negative loop.
class EchoSolver : public ConsistencySolver {
 public:
  SubsetErrors Solve(const std::vector<int>& active) override {
    for (const int l : active) {
      if (l < 0) throw std::runtime_error("negative loop");
    }
    SubsetErrors out;
    for (const int l : active) out.loop_chi2.push_back(l);
    out.total_chi2 = std::accumulate(active.begin(), active.end(), 0.0);
    out.num_edges = static_cast<int>(active.size());
    return out;
  }
  int residual_dim() const override { return 3; }
};

TEST(ForEachInParallel, CallsEveryIndexOnce) {
  for (const int threads : {1, 2, 7}) {
    std::vector<std::atomic<int>> calls(100);
    ForEachInParallel(calls.size(), threads, [&](size_t k) { ++calls[k]; });
    for (size_t k = 0; k < calls.size(); ++k) {
      EXPECT_EQ(calls[k].load(), 1) << "index " << k << ", " << threads;
    }
  }
  ForEachInParallel(0, 4, [](size_t) { FAIL() << "no index to call"; });
}

TEST(SolveInParallel, ReturnsTheErrorsInSubsetOrder) {
  std::vector<std::vector<int>> subsets(50);
  for (int k = 0; k < 50; ++k) subsets[k] = {k, k + 100};
  EchoSolver solver;
  for (const int threads : {1, 2, 7}) {
    int reports = 0;
    const auto errors =
        SolveInParallel(solver, subsets, threads, [&] { ++reports; });
    ASSERT_EQ(errors.size(), subsets.size());
    for (size_t k = 0; k < subsets.size(); ++k) {
      EXPECT_EQ(errors[k].loop_chi2,
                std::vector<double>(subsets[k].begin(), subsets[k].end()));
    }
    EXPECT_EQ(reports, 50);
  }
}

TEST(SolveInParallel, NothingToSolve) {
  EchoSolver solver;
  EXPECT_TRUE(SolveInParallel(solver, {}, 4).empty());
}

TEST(SolveInParallel, PassesOnTheExceptionOfASolve) {
  EchoSolver solver;
  std::vector<std::vector<int>> subsets(20, std::vector<int>{1});
  subsets[11] = {-1};
  for (const int threads : {1, 3}) {
    EXPECT_THROW(SolveInParallel(solver, subsets, threads), std::runtime_error);
  }
}

}  // namespace
}  // namespace rrr
