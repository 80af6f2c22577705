// Independent solves run side by side.
#ifndef RRR_SOLVER_SOLVE_IN_PARALLEL_H_
#define RRR_SOLVER_SOLVE_IN_PARALLEL_H_

#include <cstddef>
#include <functional>
#include <vector>

#include "rrr/solver/consistency_solver.h"

namespace rrr {

// Calls `task(k)` once for each k in [0, count), up to `threads` at a time
// (the calling thread is one of them), and returns when every call has
// returned. The tasks must be independent: each may write only what is its
// own (e.g. element k of a vector sized beforehand). An exception thrown by
// a task is rethrown here after every running task has ended; tasks not yet
// started are not started.
void ForEachInParallel(size_t count, int threads,
                       const std::function<void(size_t)>& task);

// Solves with each subset of loops in `subsets`, up to `threads` solves at a
// time (ForEachInParallel), and returns the errors in subset order: the same
// errors as solving them one after another. `on_solved`, if given, is
// called once per finished solve, never concurrently.
std::vector<SubsetErrors> SolveInParallel(
    ConsistencySolver& solver, const std::vector<std::vector<int>>& subsets,
    int threads, const std::function<void()>& on_solved = nullptr);

}  // namespace rrr

#endif  // RRR_SOLVER_SOLVE_IN_PARALLEL_H_
