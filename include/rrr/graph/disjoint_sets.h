// Disjoint sets of indices 0..n-1 (union–find), as connectivity and joined
// chains need them.
#ifndef RRR_GRAPH_DISJOINT_SETS_H_
#define RRR_GRAPH_DISJOINT_SETS_H_

#include <algorithm>
#include <numeric>
#include <vector>

namespace rrr {

// Each set is named by its lowest index.
class DisjointSets {
 public:
  explicit DisjointSets(int n) : root_(n) {
    std::iota(root_.begin(), root_.end(), 0);
  }
  // The lowest index of the set holding `k`.
  int Find(int k) {
    while (root_[k] != k) k = root_[k] = root_[root_[k]];
    return k;
  }
  // Joins the sets of `a` and `b`.
  void Join(int a, int b) {
    const int ra = Find(a), rb = Find(b);
    root_[std::max(ra, rb)] = std::min(ra, rb);
  }

 private:
  std::vector<int> root_;
};

}  // namespace rrr

#endif  // RRR_GRAPH_DISJOINT_SETS_H_
