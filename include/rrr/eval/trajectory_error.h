// Absolute trajectory error (ATE).
#ifndef RRR_EVAL_TRAJECTORY_ERROR_H_
#define RRR_EVAL_TRAJECTORY_ERROR_H_

#include <Eigen/Core>

namespace rrr {

// RMSE of the position error after the best rigid alignment (rotation and
// translation, no scale; Umeyama) of `estimate` onto `reference`. Both are
// dim × N with matching columns. Throws std::invalid_argument if the shapes
// differ or there are fewer than dim + 1 points.
double AbsoluteTrajectoryError(const Eigen::MatrixXd& estimate,
                               const Eigen::MatrixXd& reference);

}  // namespace rrr

#endif  // RRR_EVAL_TRAJECTORY_ERROR_H_
