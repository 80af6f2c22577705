#include "rrr/rrr/chi_square.h"

#include <boost/math/distributions/chi_squared.hpp>
#include <stdexcept>
#include <string>

namespace rrr {

ChiSquareQuantile::ChiSquareQuantile(double alpha) : alpha_(alpha) {
  if (!(alpha > 0.0 && alpha < 1.0)) {
    throw std::invalid_argument("alpha must be in (0, 1), got " +
                                std::to_string(alpha));
  }
}

double ChiSquareQuantile::operator()(int dof) const {
  if (dof < 1) {
    throw std::invalid_argument("chi-square needs dof >= 1, got " +
                                std::to_string(dof));
  }
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = cache_.find(dof);
  if (it != cache_.end()) return it->second;
  const double q = boost::math::quantile(
      boost::math::chi_squared_distribution<double>(dof), alpha_);
  cache_.emplace(dof, q);
  return q;
}

}  // namespace rrr
