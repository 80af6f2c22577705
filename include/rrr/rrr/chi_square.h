// χ² quantiles for the consistency gates.
#ifndef RRR_RRR_CHI_SQUARE_H_
#define RRR_RRR_CHI_SQUARE_H_

#include <mutex>
#include <unordered_map>

namespace rrr {

// χ²(alpha, dof): the alpha-quantile of the chi-square distribution with
// `dof` degrees of freedom (Boost.Math), memoized per dof. Thread-safe.
class ChiSquareQuantile {
 public:
  // Throws std::invalid_argument unless 0 < alpha < 1.
  explicit ChiSquareQuantile(double alpha);
  double alpha() const { return alpha_; }
  // Throws std::invalid_argument if dof < 1.
  double operator()(int dof) const;

 private:
  double alpha_;
  mutable std::mutex mutex_;
  mutable std::unordered_map<int, double> cache_;
};

}  // namespace rrr

#endif  // RRR_RRR_CHI_SQUARE_H_
