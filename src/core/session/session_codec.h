// How poses and matrices are stored in a session database: as blobs of
// doubles, read back checked.
#ifndef RRR_CORE_SESSION_SESSION_CODEC_H_
#define RRR_CORE_SESSION_SESSION_CODEC_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "sqlite_db.h"

namespace rrr {

inline std::vector<double> Encode(const Pose2& p) {
  return {p.x(), p.y(), p.theta()};
}
inline std::vector<double> Encode(const Pose3& p) {
  const auto& q = p.quaternion();
  const auto& t = p.translation();
  return {q.w(), q.x(), q.y(), q.z(), t.x(), t.y(), t.z()};
}
// A square matrix: if it is exactly symmetric, its upper triangle row by
// row (n(n + 1)/2 doubles), else every entry, column by column (n²). Read
// back exactly either way (FiniteMatrix).
template <class Derived>
std::vector<double> Encode(const Eigen::MatrixBase<Derived>& m) {
  const typename Derived::PlainObject plain = m;
  if (plain == plain.transpose()) {
    std::vector<double> upper;
    for (Eigen::Index r = 0; r < plain.rows(); ++r) {
      for (Eigen::Index c = r; c < plain.cols(); ++c)
        upper.push_back(plain(r, c));
    }
    return upper;
  }
  return std::vector<double>(plain.data(), plain.data() + plain.size());
}

constexpr size_t EncodedSize(const Pose2*) { return 3; }
constexpr size_t EncodedSize(const Pose3*) { return 7; }
constexpr int DimensionOf(const Pose2*) { return 2; }
constexpr int DimensionOf(const Pose3*) { return 3; }

// Reads `count` doubles from `column` of `row`, all finite, or fails naming
// `what` and the row `at` ("input 5: ").
inline std::vector<double> FiniteDoubles(const SqliteDb& db,
                                         const SqliteStatement& row, int column,
                                         size_t count, const std::string& what,
                                         const std::string& at) {
  std::vector<double> values = row.Doubles(column, count);
  for (const double v : values) {
    if (!std::isfinite(v)) {
      db.Fail(at + what + " holds a value that is not a finite number");
    }
  }
  return values;
}

// An N x N matrix from `column` of `row`, stored by Encode in either form,
// all finite, or fails naming `what` and the row `at`.
template <int N>
Eigen::Matrix<double, N, N> FiniteMatrix(const SqliteDb& db,
                                         const SqliteStatement& row, int column,
                                         const std::string& what,
                                         const std::string& at) {
  constexpr size_t kUpper = N * (N + 1) / 2;
  constexpr size_t kFull = static_cast<size_t>(N) * N;
  const size_t bytes = row.NumBytes(column);
  const size_t count = bytes / sizeof(double);
  if (bytes % sizeof(double) != 0 || (count != kUpper && count != kFull)) {
    db.Fail(at + what + " holds " + std::to_string(bytes) + " bytes, not " +
            std::to_string(kUpper) + " or " + std::to_string(kFull) +
            " numbers");
  }
  const std::vector<double> values =
      FiniteDoubles(db, row, column, count, what, at);
  Eigen::Matrix<double, N, N> m;
  if (count == kUpper) {
    size_t k = 0;
    for (int r = 0; r < N; ++r) {
      for (int c = r; c < N; ++c) m(r, c) = m(c, r) = values[k++];
    }
  } else {
    m = Eigen::Map<const Eigen::Matrix<double, N, N>>(values.data());
  }
  return m;
}

inline Pose2 DecodePose(const std::vector<double>& v, const Pose2*,
                        const std::function<void(const std::string&)>&) {
  return Pose2(v[0], v[1], v[2]);
}
inline Pose3 DecodePose(const std::vector<double>& v, const Pose3*,
                        const std::function<void(const std::string&)>& fail) {
  Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
  if (!(q.norm() > 1e-9)) fail("a quaternion is zero");
  if (std::abs(q.norm() - 1.0) > 1e-6) q.normalize();
  return Pose3(q, Eigen::Vector3d(v[4], v[5], v[6]));
}

// An information matrix from `column` of `row`, or fails naming the row
// `at`: non-finite values, a matrix that is not symmetric positive definite.
template <class Pose>
typename Constraint<Pose>::Information DecodeInformation(
    const SqliteDb& db, const SqliteStatement& row, int column,
    const std::string& at) {
  const typename Constraint<Pose>::Information information =
      FiniteMatrix<Pose::kDof>(db, row, column, "an information matrix", at);
  const bool symmetric = (information - information.transpose()).norm() <=
                         1e-9 * information.norm();
  if (!symmetric || information.llt().info() != Eigen::Success) {
    db.Fail(at + "an information matrix is not symmetric positive definite");
  }
  return information;
}

// A measurement and its information matrix from `columns` (pose, matrix)
// of `row`, or fails naming the row `at` (DecodeInformation).
template <class Pose>
void DecodeMeasurement(const SqliteDb& db, const SqliteStatement& row,
                       int pose_column, int information_column,
                       const std::string& at, Pose* z,
                       typename Constraint<Pose>::Information* information) {
  const auto fail = [&](const std::string& problem) { db.Fail(at + problem); };
  *z = DecodePose(FiniteDoubles(db, row, pose_column,
                                EncodedSize(static_cast<const Pose*>(nullptr)),
                                "a measurement", at),
                  static_cast<const Pose*>(nullptr), fail);
  *information = DecodeInformation<Pose>(db, row, information_column, at);
}

}  // namespace rrr

#endif  // RRR_CORE_SESSION_SESSION_CODEC_H_
