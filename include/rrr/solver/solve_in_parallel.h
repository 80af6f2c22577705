// Several consistency solves at once.
#ifndef RRR_SOLVER_SOLVE_IN_PARALLEL_H_
#define RRR_SOLVER_SOLVE_IN_PARALLEL_H_

#include <functional>
#include <vector>

#include "rrr/solver/consistency_solver.h"

namespace rrr {

// Solves with each subset of loops in `subsets`, up to `threads` solves at a
// time (the calling thread is one of them), and returns the errors in subset
// order: the same errors as solving them one after another. `on_solved`, if
// given, is called once per finished solve, never concurrently. An exception
// thrown by a solve is rethrown here after every running solve has ended.
std::vector<SubsetErrors> SolveInParallel(
    ConsistencySolver& solver, const std::vector<std::vector<int>>& subsets,
    int threads, const std::function<void()>& on_solved = nullptr);

}  // namespace rrr

#endif  // RRR_SOLVER_SOLVE_IN_PARALLEL_H_
