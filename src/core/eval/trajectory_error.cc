#include "rrr/eval/trajectory_error.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

namespace rrr {

double AbsoluteTrajectoryError(const Eigen::MatrixXd& estimate,
                               const Eigen::MatrixXd& reference) {
  if (estimate.rows() != reference.rows() ||
      estimate.cols() != reference.cols()) {
    throw std::invalid_argument("ATE: trajectories differ in shape");
  }
  if (estimate.cols() < estimate.rows() + 1) {
    throw std::invalid_argument("ATE: too few associated poses");
  }
  const Eigen::MatrixXd t = Eigen::umeyama(estimate, reference, false);
  const long d = estimate.rows();
  const Eigen::MatrixXd aligned = (t.topLeftCorner(d, d) * estimate).colwise() +
                                  t.topRightCorner(d, 1).col(0);
  return std::sqrt((aligned - reference).colwise().squaredNorm().mean());
}

}  // namespace rrr
