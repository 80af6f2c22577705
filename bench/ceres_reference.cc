// An independent reference for `rrr optimize`: the same least-squares
// problem (odometry and every loop of a g2o file, the same residual
// Log(z⁻¹ · x_i⁻¹ · x_j) weighted by each edge's information, the first pose
// and FIX poses held, from the odometry chain) minimized by Ceres Solver's
// Levenberg–Marquardt with sparse normal Cholesky. Reads the file as rrr
// does (lenient reading), and prints one JSON object: the error before and
// after (Σ rᵀ Ω r, evaluated by rrr's own edge error), iterations, Ceres's
// termination, and the seconds Ceres took.
//
//   ceres_reference IN.g2o [--max-iterations 100]
#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "json_of_graph.h"
#include "rrr/io/g2o.h"
#include "rrr/solver/chordal_initialization.h"
#include "rrr/solver/edge_error.h"
#include "rrr/solver/pose_graph_solver.h"

namespace rrr {
namespace {

// A pose as Ceres's parameter block (ambient coordinates) and the
// Jacobian P of x ⊞ δ = x · Exp(δ) at δ = 0 with a left inverse P⁺.
template <class Pose>
struct Ambient;

template <>
struct Ambient<Pose2> {
  static constexpr int kSize = 3;  // x, y, θ
  static void Store(const Pose2& p, double* a) {
    a[0] = p.x();
    a[1] = p.y();
    a[2] = p.theta();
  }
  static Pose2 Load(const double* a) { return Pose2(a[0], a[1], a[2]); }
  static Eigen::Matrix<double, 3, 3> Plus(const double* a) {
    Eigen::Matrix<double, 3, 3> p = Eigen::Matrix<double, 3, 3>::Identity();
    p.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(a[2]).toRotationMatrix();
    return p;
  }
  static Eigen::Matrix<double, 3, 3> LeftInverse(const double* a) {
    return Plus(a).transpose();
  }
};

template <>
struct Ambient<Pose3> {
  static constexpr int kSize = 7;  // t, then q as (x, y, z, w)
  static void Store(const Pose3& p, double* a) {
    Eigen::Map<Eigen::Vector3d> t(a);
    Eigen::Map<Eigen::Vector4d> q(a + 3);
    t = p.translation();
    q = p.quaternion().coeffs();
  }
  static Pose3 Load(const double* a) {
    return Pose3(Eigen::Quaterniond(a[6], a[3], a[4], a[5]),
                 Eigen::Vector3d(a[0], a[1], a[2]));
  }
  static Eigen::Matrix<double, 7, 6> Plus(const double* a) {
    const Eigen::Quaterniond q(a[6], a[3], a[4], a[5]);
    Eigen::Matrix<double, 7, 6> p = Eigen::Matrix<double, 7, 6>::Zero();
    p.topLeftCorner<3, 3>() = q.toRotationMatrix();
    // q ⊗ (1, φ/2): d(vector)/dφ = (w I + [v]×)/2, d(w)/dφ = −vᵀ/2.
    Eigen::Matrix3d cross;
    cross << 0, -q.z(), q.y(), q.z(), 0, -q.x(), -q.y(), q.x(), 0;
    p.block<3, 3>(3, 3) = 0.5 * (q.w() * Eigen::Matrix3d::Identity() + cross);
    p.block<1, 3>(6, 3) = -0.5 * q.vec().transpose();
    return p;
  }
  // The columns of Plus are orthogonal: rotation, then norm 1/2.
  static Eigen::Matrix<double, 6, 7> LeftInverse(const double* a) {
    Eigen::Matrix<double, 6, 7> inverse = Plus(a).transpose();
    inverse.bottomRows<3>() *= 4.0;
    return inverse;
  }
};

template <class Pose>
class PoseManifold : public ceres::Manifold {
 public:
  using A = Ambient<Pose>;
  int AmbientSize() const override { return A::kSize; }
  int TangentSize() const override { return Pose::kDof; }
  bool Plus(const double* x, const double* delta,
            double* x_plus_delta) const override {
    const Eigen::Map<const typename Pose::Tangent> d(delta);
    A::Store(A::Load(x) * Pose::Exp(d), x_plus_delta);
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, A::kSize, Pose::kDof, Eigen::RowMajor>> j(
        jacobian);
    j = A::Plus(x);
    return true;
  }
  bool Minus(const double* y, const double* x,
             double* y_minus_x) const override {
    Eigen::Map<typename Pose::Tangent> d(y_minus_x);
    d = A::Load(x).between(A::Load(y)).Log();
    return true;
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, Pose::kDof, A::kSize, Eigen::RowMajor>> j(
        jacobian);
    j = A::LeftInverse(x);
    return true;
  }
};

// One edge: the residual L·r (LᵀL = Ω) with rrr's exact tangent Jacobians,
// given to Ceres in ambient coordinates through P⁺ (Ceres multiplies by P).
template <class Pose>
class EdgeCost
    : public ceres::SizedCostFunction<Pose::kDof, Ambient<Pose>::kSize,
                                      Ambient<Pose>::kSize> {
 public:
  using A = Ambient<Pose>;
  explicit EdgeCost(const Constraint<Pose>& edge)
      : measurement_(edge.measurement),
        sqrt_information_(edge.information.llt().matrixU()) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    typename Pose::Jacobian ji, jj;
    const typename Pose::Tangent r = EdgeResidualAndJacobians(
        measurement_, A::Load(parameters[0]), A::Load(parameters[1]), &ji, &jj);
    Eigen::Map<typename Pose::Tangent> weighted(residuals);
    weighted = sqrt_information_ * r;
    using Out = Eigen::Matrix<double, Pose::kDof, A::kSize, Eigen::RowMajor>;
    if (jacobians && jacobians[0]) {
      Eigen::Map<Out> j(jacobians[0]);
      j = sqrt_information_ * ji * A::LeftInverse(parameters[0]);
    }
    if (jacobians && jacobians[1]) {
      Eigen::Map<Out> j(jacobians[1]);
      j = sqrt_information_ * jj * A::LeftInverse(parameters[1]);
    }
    return true;
  }

 private:
  Pose measurement_;
  typename Pose::Jacobian sqrt_information_;
};

template <class Pose>
nlohmann::json Solve(const PoseGraph<Pose>& graph, int max_iterations,
                     bool chordal) {
  using A = Ambient<Pose>;
  const PoseGraphSolver<Pose> rrr_solver(graph, 1);
  const std::vector<int> all = AllLoops(graph);
  const std::vector<Pose> start =
      chordal ? ChordalInitialization(graph, all) : rrr_solver.initial();
  std::vector<double> values(graph.num_poses() * A::kSize);
  for (int k = 0; k < graph.num_poses(); ++k) {
    A::Store(start[k], &values[k * A::kSize]);
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  PoseManifold<Pose> manifold;
  const auto add = [&](const Constraint<Pose>& e) {
    problem.AddResidualBlock(new EdgeCost<Pose>(e), nullptr,
                             &values[e.from * A::kSize],
                             &values[e.to * A::kSize]);
  };
  for (const auto& e : graph.odometry()) add(e);
  for (const auto& e : graph.loops()) add(e);
  for (int k = 0; k < graph.num_poses(); ++k) {
    problem.SetManifold(&values[k * A::kSize], &manifold);
  }
  problem.SetParameterBlockConstant(&values[0]);
  for (const int k : graph.fixed()) {
    problem.SetParameterBlockConstant(&values[k * A::kSize]);
  }

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = max_iterations;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  std::vector<Pose> x(graph.num_poses());
  for (int k = 0; k < graph.num_poses(); ++k) {
    x[k] = A::Load(&values[k * A::kSize]);
  }
  return {
      {"initial_chi2", rrr_solver.Evaluate(all, start).total_chi2},
      {"final_chi2", rrr_solver.Evaluate(all, x).total_chi2},
      {"iterations", summary.iterations.size() - 1},
      {"successful_steps", summary.num_successful_steps},
      {"termination", ceres::TerminationTypeToString(summary.termination_type)},
      {"converged", summary.termination_type == ceres::CONVERGENCE},
      {"seconds", summary.total_time_in_seconds}};
}

}  // namespace
}  // namespace rrr

int main(int argc, char** argv) {
  const char* usage =
      "usage: ceres_reference IN.g2o [--max-iterations N] "
      "[--init odometry|chordal]\n";
  if (argc < 2) {
    std::cerr << usage;
    return 2;
  }
  int max_iterations = 100;
  bool chordal = false;
  for (int k = 2; k < argc; k += 2) {
    const std::string flag = argv[k];
    if (k + 1 >= argc) {
      std::cerr << usage;
      return 2;
    }
    const std::string value = argv[k + 1];
    if (flag == "--max-iterations") {
      max_iterations = std::atoi(value.c_str());
    } else if (flag == "--init" &&
               (value == "odometry" || value == "chordal")) {
      chordal = value == "chordal";
    } else {
      std::cerr << usage;
      return 2;
    }
  }
  return rrr::PrintJsonOfGraph("ceres_reference", argv[1], [&](const auto& g) {
    return rrr::Solve(g, max_iterations, chordal);
  });
}
