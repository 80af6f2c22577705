#include "rrr/solver/solve_in_parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

namespace rrr {

void ForEachInParallel(size_t count, int threads,
                       const std::function<void(size_t)>& task) {
  std::atomic<size_t> next{0};
  std::mutex mutex;  // guards `failure`
  std::exception_ptr failure;
  const auto work = [&] {
    for (size_t k = next++; k < count; k = next++) {
      try {
        task(k);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        next = count;  // start nothing new
      }
    }
  };
  const size_t running =
      std::min(count, static_cast<size_t>(std::max(threads, 1)));
  std::vector<std::thread> pool;
  for (size_t t = 1; t < running; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

std::vector<SubsetErrors> SolveInParallel(
    ConsistencySolver& solver, const std::vector<std::vector<int>>& subsets,
    int threads, const std::function<void()>& on_solved) {
  std::vector<SubsetErrors> results(subsets.size());
  std::mutex mutex;  // guards calls of `on_solved`
  ForEachInParallel(subsets.size(), threads, [&](size_t k) {
    results[k] = solver.Solve(subsets[k]);
    if (on_solved) {
      const std::lock_guard<std::mutex> lock(mutex);
      on_solved();
    }
  });
  return results;
}

}  // namespace rrr
