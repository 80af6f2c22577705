#include "rrr/solver/chordal_initialization.h"

#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"

namespace rrr {
namespace {

template <int D>
using Square = Eigen::Matrix<double, D, D>;

// The rotation nearest to `m` in the Frobenius norm.
template <int D>
Square<D> NearestRotation(const Square<D>& m) {
  const Eigen::JacobiSVD<Square<D>> svd(
      m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Square<D> fix = Square<D>::Identity();
  fix(D - 1, D - 1) = (svd.matrixU() * svd.matrixV().transpose()).determinant();
  return svd.matrixU() * fix * svd.matrixV().transpose();
}

Pose2 PoseFrom(const Eigen::Matrix2d& r, const Eigen::Vector2d& t) {
  return Pose2(t.x(), t.y(), std::atan2(r(1, 0), r(0, 0)));
}

Pose3 PoseFrom(const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  return Pose3(Eigen::Quaterniond(r).normalized(), t);
}

// Solves the normal equations `h` x = `rhs` (one column per right-hand
// side); throws naming `what` if they cannot be solved.
Eigen::MatrixXd SolveNormal(const Eigen::SparseMatrix<double>& h,
                            const Eigen::MatrixXd& rhs, const char* what) {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(h);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error(std::string("chordal initialization: the ") +
                             what + " cannot be solved");
  }
  return solver.solve(rhs);
}

}  // namespace

template <class Pose>
std::vector<Pose> ChordalInitialization(const PoseGraph<Pose>& graph,
                                        const std::vector<int>& loops) {
  constexpr int d = Pose::kTranslationDim;
  const int n = graph.num_poses();
  std::vector<const Constraint<Pose>*> edges;
  for (const auto& e : graph.odometry()) edges.push_back(&e);
  for (const int k : loops) edges.push_back(&graph.loops()[k]);
  const std::string unreached = graph.CheckConnected(loops);
  if (!unreached.empty()) {
    throw std::runtime_error("chordal initialization: " + unreached);
  }
  std::vector<Pose> out(n);
  if (n == 0) return out;
  out[0] = graph.estimates()[0];
  if (n == 1) return out;
  // Unknowns: poses 1..n-1, d per pose (one row of R, or t); pose 0 is
  // known. A residual a·u_i + b·u_j (d×d blocks a, b) with weight w adds
  // w·[aᵀa aᵀb; bᵀa bᵀb] to the normal matrix; a known u_0 goes to the rhs.
  const int m = d * (n - 1);
  std::vector<Eigen::Triplet<double>> rotation_terms, translation_terms;
  Eigen::MatrixXd rotation_rhs = Eigen::MatrixXd::Zero(m, d);
  Eigen::VectorXd translation_rhs = Eigen::VectorXd::Zero(m);
  const Square<d> r0 = graph.estimates()[0].rotation();
  const auto add = [&](std::vector<Eigen::Triplet<double>>* terms, int i, int j,
                       const Square<d>& a, const Square<d>& b,
                       const Square<d>& w) {
    const int pose[2] = {i, j};
    const Square<d> block[2] = {a, b};
    for (int p = 0; p < 2; ++p) {
      for (int q = 0; q < 2; ++q) {
        if (pose[p] == 0 || pose[q] == 0) continue;
        const Square<d> hpq = block[p].transpose() * w * block[q];
        for (int r = 0; r < d; ++r) {
          for (int c = 0; c < d; ++c) {
            terms->emplace_back(d * (pose[p] - 1) + r, d * (pose[q] - 1) + c,
                                hpq(r, c));
          }
        }
      }
    }
  };
  // Rotations: for each row k of R, R_ijᵀ·(row k of R_i)ᵀ − (row k of R_j)ᵀ.
  for (const auto* e : edges) {
    const Square<d> rij = e->measurement.rotation();
    const double w =
        e->information
            .template bottomRightCorner<Pose::kDof - d, Pose::kDof - d>()
            .trace() /
        (Pose::kDof - d);
    const Square<d> a = rij.transpose(), b = -Square<d>::Identity();
    add(&rotation_terms, e->from, e->to, a, b, w * Square<d>::Identity());
    for (int k = 0; k < d; ++k) {
      const Eigen::Matrix<double, d, 1> row0 = r0.row(k).transpose();
      if (e->from == 0 && e->to != 0) {
        rotation_rhs.block<d, 1>(d * (e->to - 1), k) -=
            w * b.transpose() * a * row0;
      } else if (e->to == 0 && e->from != 0) {
        rotation_rhs.block<d, 1>(d * (e->from - 1), k) -=
            w * a.transpose() * b * row0;
      }
    }
  }
  Eigen::SparseMatrix<double> h(m, m);
  h.setFromTriplets(rotation_terms.begin(), rotation_terms.end());
  const Eigen::MatrixXd rows = SolveNormal(h, rotation_rhs, "rotations");
  std::vector<Square<d>> rotation(n);
  rotation[0] = r0;
  for (int p = 1; p < n; ++p) {
    rotation[p] =
        NearestRotation<d>(rows.block<d, d>(d * (p - 1), 0).transpose());
  }
  // Translations: t_j − t_i − R_i·t_ij, weighted by R_i·Ω_t·R_iᵀ.
  const Eigen::Matrix<double, d, 1> t0 = graph.estimates()[0].translation();
  for (const auto* e : edges) {
    const Square<d>& ri = rotation[e->from];
    const Square<d> w =
        ri * e->information.template topLeftCorner<d, d>() * ri.transpose();
    const Square<d> a = -Square<d>::Identity(), b = Square<d>::Identity();
    add(&translation_terms, e->from, e->to, a, b, w);
    // Residual a·t_i + b·t_j − c: −c's share goes to each side's rhs.
    const Eigen::Matrix<double, d, 1> c = ri * e->measurement.translation();
    Eigen::Matrix<double, d, 1> residual_known = -c;
    if (e->from == 0) residual_known += a * t0;
    if (e->to == 0) residual_known += b * t0;
    if (e->from != 0) {
      translation_rhs.segment<d>(d * (e->from - 1)) -=
          a.transpose() * w * residual_known;
    }
    if (e->to != 0) {
      translation_rhs.segment<d>(d * (e->to - 1)) -=
          b.transpose() * w * residual_known;
    }
  }
  h.setZero();
  h.setFromTriplets(translation_terms.begin(), translation_terms.end());
  const Eigen::VectorXd t = SolveNormal(h, translation_rhs, "translations");
  for (int p = 1; p < n; ++p) {
    const Eigen::Matrix<double, d, 1> tp = t.segment<d>(d * (p - 1));
    out[p] = PoseFrom(rotation[p], tp);
  }
  return out;
}

template std::vector<Pose2> ChordalInitialization(const PoseGraph<Pose2>&,
                                                  const std::vector<int>&);
template std::vector<Pose3> ChordalInitialization(const PoseGraph<Pose3>&,
                                                  const std::vector<int>&);

}  // namespace rrr
