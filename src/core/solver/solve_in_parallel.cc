#include "rrr/solver/solve_in_parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace rrr {

std::vector<SubsetErrors> SolveInParallel(
    ConsistencySolver& solver, const std::vector<std::vector<int>>& subsets,
    int threads, const std::function<void()>& on_solved) {
  std::vector<SubsetErrors> results(subsets.size());
  std::atomic<size_t> next{0};
  std::mutex mutex;  // guards `failure` and calls of `on_solved`
  std::exception_ptr failure;
  const auto work = [&] {
    for (size_t k = next++; k < subsets.size(); k = next++) {
      try {
        results[k] = solver.Solve(subsets[k]);
        if (on_solved) {
          const std::lock_guard<std::mutex> lock(mutex);
          on_solved();
        }
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next = subsets.size();  // start nothing new
      }
    }
  };
  const size_t running =
      std::min(subsets.size(), static_cast<size_t>(std::max(threads, 1)));
  std::vector<std::thread> pool;
  for (size_t t = 1; t < running; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  return results;
}

}  // namespace rrr
