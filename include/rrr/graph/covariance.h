// From a covariance to the information matrix an edge carries.
#ifndef RRR_GRAPH_COVARIANCE_H_
#define RRR_GRAPH_COVARIANCE_H_

#include <Eigen/Core>
#include <string>

namespace rrr {

// Covariances less well conditioned than this have no usable inverse.
constexpr double kMinReciprocalCondition = 1e-14;

// Sets `*information` to the inverse of the symmetric `covariance` and
// returns true if that inverse is usable: the covariance positive definite,
// its reciprocal condition number at least kMinReciprocalCondition, and the
// inverse finite and symmetric positive definite. Otherwise returns false,
// leaves `*information` unchanged and, if `why` is given, says which.
// Instantiated for 3 × 3 and 6 × 6.
template <int D>
bool InformationFromCovariance(const Eigen::Matrix<double, D, D>& covariance,
                               Eigen::Matrix<double, D, D>* information,
                               std::string* why = nullptr);

}  // namespace rrr

#endif  // RRR_GRAPH_COVARIANCE_H_
