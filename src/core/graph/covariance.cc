#include "rrr/graph/covariance.h"

#include <Eigen/Cholesky>

namespace rrr {

template <int D>
bool InformationFromCovariance(const Eigen::Matrix<double, D, D>& covariance,
                               Eigen::Matrix<double, D, D>* information,
                               std::string* why) {
  using M = Eigen::Matrix<double, D, D>;
  const auto fail = [why](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  const Eigen::LLT<M> llt(covariance);
  if (llt.info() != Eigen::Success) {
    return fail("the covariance is not positive definite");
  }
  if (llt.rcond() < kMinReciprocalCondition) {
    return fail(
        "the covariance is numerically singular (reciprocal condition " +
        std::to_string(llt.rcond()) + ")");
  }
  const M inverse = llt.solve(M::Identity());
  const M symmetric = 0.5 * (inverse + inverse.transpose());
  if (!symmetric.allFinite() || symmetric.llt().info() != Eigen::Success) {
    return fail("the covariance has no finite positive definite inverse");
  }
  *information = symmetric;
  return true;
}

template bool InformationFromCovariance<3>(const Eigen::Matrix3d&,
                                           Eigen::Matrix3d*, std::string*);
template bool InformationFromCovariance<6>(const Eigen::Matrix<double, 6, 6>&,
                                           Eigen::Matrix<double, 6, 6>*,
                                           std::string*);

}  // namespace rrr
