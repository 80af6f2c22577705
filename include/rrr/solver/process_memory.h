// How the process holds the memory its solves free.
#ifndef RRR_SOLVER_PROCESS_MEMORY_H_
#define RRR_SOLVER_PROCESS_MEMORY_H_

namespace rrr {

// Makes the allocator keep freed memory in the process instead of returning
// it to the kernel: blocks up to kArenaBlockLimit are served from an arena
// instead of a mapping of their own, and the main arena is trimmed only
// past 1 GB free. A verifier sets up and frees thousands of sparse
// problems, and each page mapped afresh costs a page fault. A thread's own
// arena returns freed memory sooner than the main one, so the largest solves
// belong on the main thread. Call it once, at start-up. Returns whether the
// allocator took both settings (false where it is not glibc: nothing is
// changed).
constexpr int kArenaBlockLimit = 256 << 20;
bool KeepFreedMemory();

}  // namespace rrr

#endif  // RRR_SOLVER_PROCESS_MEMORY_H_
